// The warnings of one scene import, shared by the glTF and COLLADA importers.
// An importer keeps loading past what it approximates or drops; the user
// wants to know each kind of approximation once, not once per triangle, and
// only when the file loaded at all (a file that fails prints only its error).
// So warnings are collected while the file loads and reported together at
// the end, one line per kind, in the order each kind first occurred.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace vkpath::scene {

class ImportWarnings {
  public:
    explicit ImportWarnings(std::string file) : m_file(std::move(file)) {}

    // A kind named by its `message`, counted in `unit`s ("material",
    // "triangle") with the first one's name: "<message> (3 materials, first:
    // red)". An empty `unit` prints no count.
    void addCounted(const std::string& message, const std::string& unit = {},
                    const std::string& example = {}, size_t count = 1);

    // A kind whose first occurrence's `text` (naming what it concerns) stands
    // for all of them: "<text> (4 like this)" when the kind recurs.
    void addExample(const std::string& kind, std::string text);

    // "<file>: <line>" per kind, in order of first occurrence.
    std::vector<std::string> lines() const;

    // Prints each line to stderr as "vkpath: warning: <file>: <line>"; with
    // `copy`, also appends the lines (without that prefix) to it.
    void report(std::vector<std::string>* copy = nullptr) const;

  private:
    struct Entry {
        std::string kind;           // what groups occurrences
        std::string text;           // printed: the message, or the first occurrence's text
        std::string unit, example;  // addCounted only
        size_t count = 0;
    };
    Entry& entry(const std::string& kind, std::string text);

    std::string m_file;
    std::vector<Entry> m_entries;  // in order of first occurrence
};

}  // namespace vkpath::scene
