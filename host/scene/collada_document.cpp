#include "scene/collada_document.h"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>

#include "input_error.h"

namespace vkpath::scene::collada {
namespace {

// Whitespace-separated tokens of an element's text.
template <class F>
void forEachToken(std::string_view text, F&& f) {
    size_t i = 0;
    while (i < text.size()) {
        while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
        size_t j = i;
        while (j < text.size() && !std::isspace(static_cast<unsigned char>(text[j]))) ++j;
        if (j > i) f(text.substr(i, j - i));
        i = j;
    }
}

}  // namespace

bool parseNumber(std::string_view token, double& value) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec == std::errc::result_out_of_range) {
        // Beyond double: an infinity the caller's finiteness checks reject.
        value = token.front() == '-' ? -HUGE_VAL : HUGE_VAL;
        return true;
    }
    return ec == std::errc() && end == token.data() + token.size();
}

bool allFinite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::string vecString(const glm::vec3& v) {
    return fmt::format("({:g}, {:g}, {:g})", v.x, v.y, v.z);
}

std::string nameOf(pugi::xml_node node) {
    if (const char* name = node.attribute("name").as_string(nullptr); name && *name) return name;
    if (const char* id = node.attribute("id").as_string(nullptr); id && *id) return id;
    return fmt::format("(unnamed {})", node.name());
}

pugi::xml_node cmuTechnique(pugi::xml_node owner) {
    for (pugi::xml_node extra : owner.children("extra"))
        for (pugi::xml_node technique : extra.children("technique"))
            if (std::string_view(technique.attribute("profile").as_string()) == "CMU462")
                return technique;
    return {};
}

Document::Document(const std::filesystem::path& path) : m_file(path.string()) {
    const pugi::xml_parse_result parsed = m_xml.load_file(path.c_str());
    if (parsed.status == pugi::status_file_not_found) fail("no such file");
    if (parsed.status == pugi::status_io_error || parsed.status == pugi::status_out_of_memory)
        fail(fmt::format("cannot read: {}", parsed.description()));
    if (!parsed)
        fail(fmt::format("malformed XML at byte {}: {}", parsed.offset, parsed.description()));
    if (std::string_view(root().name()) != "COLLADA")
        fail(fmt::format("not a COLLADA document (the root element is <{}>)", root().name()));

    // Iterative: the XML may nest deeper than the stack allows recursion.
    std::vector<pugi::xml_node> stack{root()};
    while (!stack.empty()) {
        const pugi::xml_node node = stack.back();
        stack.pop_back();
        if (const char* id = node.attribute("id").as_string(nullptr); id && *id)
            m_ids.emplace(id, node);  // the first of duplicate ids wins
        for (pugi::xml_node child : node.children())
            if (child.type() == pugi::node_element) stack.push_back(child);
    }
}

void Document::fail(const std::string& what) const {
    throw InputError(fmt::format("{}: {}", m_file, what));
}

std::vector<double> Document::numbers(pugi::xml_node element, const std::string& what) const {
    std::vector<double> out;
    forEachToken(element.child_value(), [&](std::string_view token) {
        double v = 0;
        if (!parseNumber(token, v)) fail(fmt::format("{}: '{}' is not a number", what, token));
        // Finite in the file, an infinity as the scene's 32-bit floats.
        if (std::isfinite(v) && std::abs(v) > double(std::numeric_limits<float>::max()))
            fail(fmt::format("{}: '{}' is beyond the range of a 32-bit float", what, token));
        out.push_back(v);
    });
    return out;
}

std::vector<uint32_t> Document::indices(pugi::xml_node element, const std::string& what) const {
    std::vector<uint32_t> out;
    forEachToken(element.child_value(), [&](std::string_view token) {
        uint32_t v = 0;
        const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
        if (ec != std::errc() || end != token.data() + token.size())
            fail(fmt::format("{}: '{}' is not an index", what, token));
        out.push_back(v);
    });
    return out;
}

glm::vec3 Document::color(pugi::xml_node element, const std::string& what) const {
    if (!element) fail(fmt::format("{} is missing", what));
    const std::vector<double> v = numbers(element, what);
    if (v.size() < 3) fail(fmt::format("{} has {} numbers, needs 3", what, v.size()));
    const glm::vec3 c(v[0], v[1], v[2]);
    if (!allFinite(c) || c.x < 0 || c.y < 0 || c.z < 0)
        fail(fmt::format("{} {} is not a finite, non-negative colour", what, vecString(c)));
    return c;
}

double Document::scalar(pugi::xml_node element, const std::string& what) const {
    if (!element) fail(fmt::format("{} is missing", what));
    const std::vector<double> v = numbers(element, what);
    if (v.size() != 1) fail(fmt::format("{} has {} numbers, needs 1", what, v.size()));
    if (!std::isfinite(v[0])) fail(fmt::format("{} is not finite", what));
    return v[0];
}

pugi::xml_node Document::resolve(const char* url, const char* kind,
                                 const std::string& context) const {
    const std::string_view ref(url ? url : "");
    if (ref.empty()) fail(fmt::format("{}: no {} reference", context, kind));
    if (ref.front() != '#')
        fail(
            fmt::format("{}: {} reference '{}' is not in this file (external references are not "
                        "supported)",
                        context, kind, ref));
    const auto it = m_ids.find(std::string(ref.substr(1)));
    if (it == m_ids.end())
        fail(fmt::format("{}: missing referenced {} id '{}'", context, kind, ref.substr(1)));
    if (std::string_view(it->second.name()) != kind)
        fail(fmt::format("{}: '{}' is a <{}>, not a <{}>", context, ref, it->second.name(), kind));
    return it->second;
}

// ===========================================================================
// Document and node hierarchy
// ===========================================================================

}  // namespace vkpath::scene::collada
