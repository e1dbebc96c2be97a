#include "scene/import_warnings.h"

#include <fmt/format.h>

#include <cstdio>

namespace vkpath::scene {

ImportWarnings::Entry& ImportWarnings::entry(const std::string& kind, std::string text) {
    for (Entry& e : m_entries)
        if (e.kind == kind) return e;
    m_entries.push_back({kind, std::move(text), {}, {}, 0});
    return m_entries.back();
}

void ImportWarnings::addCounted(const std::string& message, const std::string& unit,
                                const std::string& example, size_t count) {
    Entry& e = entry(message, message);
    if (e.count == 0) {
        e.unit = unit;
        e.example = example;
    }
    e.count += count;
}

void ImportWarnings::addExample(const std::string& kind, std::string text) {
    ++entry(kind, std::move(text)).count;
}

std::vector<std::string> ImportWarnings::lines() const {
    std::vector<std::string> out;
    for (const Entry& e : m_entries) {
        std::string line = fmt::format("{}: {}", m_file, e.text);
        if (!e.unit.empty())
            line += fmt::format(" ({} {}{}{})", e.count, e.unit, e.count == 1 ? "" : "s",
                                e.example.empty() ? "" : ", first: " + e.example);
        else if (e.count > 1)
            line += fmt::format(" ({} like this)", e.count);
        out.push_back(std::move(line));
    }
    return out;
}

void ImportWarnings::report(std::vector<std::string>* copy) const {
    for (const std::string& line : lines()) {
        std::fprintf(stderr, "vkpath: warning: %s\n", line.c_str());
        if (copy) copy->push_back(line);
    }
}

}  // namespace vkpath::scene
