// A small XML scanner for VTK's XML files (.vtu, .pvd): elements, attributes and the character
// data of leaf-like elements, enough for what VTK writes, not a general XML parser (no DTDs, no
// CDATA sections, no namespaces). Positions refer to the scanned text, so that large base64 or
// ASCII arrays are never copied.
//
// VTK's <AppendedData> section holds raw bytes that are not XML: scanning stops after its "_"
// marker and reports where the data begin.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace vs {

struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;  // entities decoded
  std::vector<XmlElement> children;
  // The last non-blank run of character data directly inside this element: a DataArray's values
  // (which VTK writes after any <InformationKey> children). Empty range when there is none.
  size_t text_begin = 0, text_end = 0;

  const std::string* attribute(std::string_view key) const;    // nullptr when absent
  const XmlElement* child(std::string_view child_name) const;  // the first one, or nullptr
};

struct XmlDocument {
  XmlElement root;
  // Set when an <AppendedData> start tag was met: its attributes (in `appended`) and the offset of
  // the first byte after its "_" marker. The elements still open there are returned as closed.
  bool has_appended = false;
  XmlElement appended;
  size_t appended_begin = 0;
};

// Scans `text` (the whole file); InputError naming `file` for anything malformed or truncated.
XmlDocument scan_xml(std::string_view text, const std::string& file);

}  // namespace vs
