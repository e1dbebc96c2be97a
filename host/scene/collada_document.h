// A COLLADA document as the importer reads it: the XML (pugixml), its ids,
// and the checked readers of numbers, colours and references that every part
// of the importer uses, each failing with one InputError line naming the file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <glm/glm.hpp>
#include <pugixml.hpp>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace vkpath::scene::collada {

class Document {
  public:
    // Parses `path`; throws InputError on unreadable or malformed XML, or a
    // root element other than <COLLADA>.
    explicit Document(const std::filesystem::path& path);
    Document(const Document&) = delete;
    Document& operator=(const Document&) = delete;

    const std::string& file() const { return m_file; }
    pugi::xml_node root() const { return m_xml.document_element(); }

    [[noreturn]] void fail(const std::string& what) const;

    // The element's whitespace-separated numbers (a leading '+' allowed;
    // values beyond double are infinities for the caller to refuse).
    std::vector<double> numbers(pugi::xml_node element, const std::string& what) const;
    // The element's whitespace-separated unsigned 32-bit indices.
    std::vector<uint32_t> indices(pugi::xml_node element, const std::string& what) const;
    // The first three numbers: finite and non-negative.
    glm::vec3 color(pugi::xml_node element, const std::string& what) const;
    // Exactly one finite number.
    double scalar(pugi::xml_node element, const std::string& what) const;
    // The element of kind `kind` that the "#id" `url` names.
    pugi::xml_node resolve(const char* url, const char* kind, const std::string& context) const;

  private:
    std::string m_file;
    pugi::xml_document m_xml;
    std::unordered_map<std::string, pugi::xml_node> m_ids;
};

// One number, as Document::numbers reads each.
bool parseNumber(std::string_view token, double& value);

// The element's name attribute, else its id, else "(unnamed <kind>)".
std::string nameOf(pugi::xml_node node);

// The <extra><technique profile="CMU462"> of `owner` (Scotty3D's profile).
pugi::xml_node cmuTechnique(pugi::xml_node owner);

bool allFinite(const glm::vec3& v);
std::string vecString(const glm::vec3& v);

}  // namespace vkpath::scene::collada
