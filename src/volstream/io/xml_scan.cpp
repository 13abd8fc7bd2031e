#include "volstream/io/xml_scan.h"

#include <charconv>
#include <cstdint>

#include "volstream/core/error.h"

namespace vs {

const std::string* XmlElement::attribute(std::string_view key) const {
  for (const auto& [k, v] : attributes)
    if (k == key) return &v;
  return nullptr;
}

const XmlElement* XmlElement::child(std::string_view child_name) const {
  for (const XmlElement& c : children)
    if (c.name == child_name) return &c;
  return nullptr;
}

namespace {

// VTK files nest about five deep; the cap keeps hostile input from growing the stack without end.
constexpr size_t kMaxDepth = 64;

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
bool is_name_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
         c == '.' || c == ':';
}

void append_utf8(std::string& out, uint32_t cp) {
  if (cp < 0x80) {
    out += char(cp);
  } else if (cp < 0x800) {
    out += char(0xC0 | (cp >> 6));
    out += char(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += char(0xE0 | (cp >> 12));
    out += char(0x80 | ((cp >> 6) & 0x3F));
    out += char(0x80 | (cp & 0x3F));
  } else {
    out += char(0xF0 | (cp >> 18));
    out += char(0x80 | ((cp >> 12) & 0x3F));
    out += char(0x80 | ((cp >> 6) & 0x3F));
    out += char(0x80 | (cp & 0x3F));
  }
}

class Scanner {
 public:
  Scanner(std::string_view text, const std::string& file) : text_(text), file_(file) {}

  XmlDocument scan() {
    XmlDocument doc;
    std::vector<XmlElement> open;  // open.back() is the innermost element being built
    bool root_done = false;
    while (!root_done && !doc.has_appended) {
      const size_t lt = text_.find('<', pos_);
      if (lt == std::string_view::npos) break;
      note_text(open, pos_, lt);
      pos_ = lt;
      if (starts_with("<?")) {
        skip_past("?>");
      } else if (starts_with("<!--")) {
        skip_past("-->");
      } else if (starts_with("<![CDATA[")) {
        fail("CDATA sections are not supported");
      } else if (starts_with("<!")) {
        skip_past(">");
      } else if (starts_with("</")) {
        close_element(open, doc, root_done);
      } else {
        open_element(open, doc, root_done);
      }
    }
    if (doc.has_appended) {
      while (!open.empty()) close_top(open, doc, root_done);
    }
    if (open.size() || !root_done) {
      fail(open.empty() ? std::string("no XML root element (not a VTK XML file?)")
                        : "truncated file: <" + open.back().name + "> is not closed");
    }
    return doc;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    input_error(file_, what + " (at byte " + std::to_string(pos_) + ")");
  }
  bool starts_with(std::string_view s) const { return text_.substr(pos_, s.size()) == s; }
  void skip_past(std::string_view end) {
    const size_t at = text_.find(end, pos_);
    if (at == std::string_view::npos) fail("truncated file: unterminated markup");
    pos_ = at + end.size();
  }
  void skip_spaces() {
    while (pos_ < text_.size() && is_space(text_[pos_])) ++pos_;
  }
  char peek() const {
    if (pos_ >= text_.size()) fail("truncated file inside a tag");
    return text_[pos_];
  }
  std::string name() {
    const size_t begin = pos_;
    while (pos_ < text_.size() && is_name_char(text_[pos_])) ++pos_;
    if (pos_ == begin) fail("expected a name in a tag");
    return std::string(text_.substr(begin, pos_ - begin));
  }

  // Character data between tags: remembered for the innermost open element when not blank.
  void note_text(std::vector<XmlElement>& open, size_t begin, size_t end) const {
    if (open.empty()) return;
    for (size_t i = begin; i < end; ++i) {
      if (!is_space(text_[i])) {
        open.back().text_begin = begin;
        open.back().text_end = end;
        return;
      }
    }
  }

  std::string attribute_value() {
    const char quote = peek();
    if (quote != '"' && quote != '\'') fail("expected a quoted attribute value");
    ++pos_;
    const size_t end = text_.find(quote, pos_);
    if (end == std::string_view::npos) fail("truncated file: unterminated attribute value");
    std::string value = decode_entities(text_.substr(pos_, end - pos_));
    pos_ = end + 1;
    return value;
  }

  std::string decode_entities(std::string_view raw) const {
    std::string out;
    for (size_t i = 0; i < raw.size(); ++i) {
      if (raw[i] != '&') {
        out += raw[i];
        continue;
      }
      const size_t semi = raw.find(';', i);
      if (semi == std::string_view::npos) fail("bad entity in an attribute value");
      const std::string_view entity = raw.substr(i + 1, semi - i - 1);
      if (entity == "lt")
        out += '<';
      else if (entity == "gt")
        out += '>';
      else if (entity == "amp")
        out += '&';
      else if (entity == "quot")
        out += '"';
      else if (entity == "apos")
        out += '\'';
      else
        append_utf8(out, character_reference(entity));
      i = semi;
    }
    return out;
  }

  uint32_t character_reference(std::string_view entity) const {
    uint32_t cp = 0;
    // "&;" too: an empty name has no digits to take (found by vtu_fuzz).
    if (entity.empty() || entity[0] != '#') fail("unknown entity &" + std::string(entity) + ";");
    const bool hex = entity.size() > 2 && (entity[1] == 'x' || entity[1] == 'X');
    const std::string_view digits = entity.substr(hex ? 2 : 1);
    if (digits.empty()) fail("unknown entity &" + std::string(entity) + ";");
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), cp, hex ? 16 : 10);
    if (ec != std::errc() || end != digits.data() + digits.size() || cp == 0 || cp > 0x10FFFF)
      fail("bad character reference &" + std::string(entity) + ";");
    return cp;
  }

  void open_element(std::vector<XmlElement>& open, XmlDocument& doc, bool& root_done) {
    ++pos_;  // '<'
    XmlElement e;
    e.name = name();
    for (;;) {
      skip_spaces();
      const char c = peek();
      if (c == '/' || c == '>') break;
      std::string key = name();
      skip_spaces();
      if (peek() != '=') fail("expected '=' after attribute " + key);
      ++pos_;
      skip_spaces();
      e.attributes.emplace_back(std::move(key), attribute_value());
    }
    const bool self_closing = peek() == '/';
    if (self_closing) {
      ++pos_;
      if (peek() != '>') fail("expected '>' after '/'");
    }
    ++pos_;  // '>'
    if (open.empty() && root_done) fail("a second root element <" + e.name + ">");
    if (open.size() >= kMaxDepth) fail("elements nested too deep");
    if (e.name == "AppendedData" && !self_closing) return start_appended(std::move(e), doc);
    open.push_back(std::move(e));
    if (self_closing) close_top(open, doc, root_done);
  }

  void start_appended(XmlElement e, XmlDocument& doc) {
    skip_spaces();
    if (pos_ >= text_.size() || text_[pos_] != '_') fail("<AppendedData> does not start with '_'");
    doc.has_appended = true;
    doc.appended = std::move(e);
    doc.appended_begin = pos_ + 1;
  }

  void close_element(std::vector<XmlElement>& open, XmlDocument& doc, bool& root_done) {
    pos_ += 2;  // "</"
    const std::string closing = name();
    skip_spaces();
    if (peek() != '>') fail("expected '>' in </" + closing + ">");
    ++pos_;
    if (open.empty() || open.back().name != closing) fail("unexpected </" + closing + ">");
    close_top(open, doc, root_done);
  }

  static void close_top(std::vector<XmlElement>& open, XmlDocument& doc, bool& root_done) {
    XmlElement done = std::move(open.back());
    open.pop_back();
    if (open.empty()) {
      doc.root = std::move(done);
      root_done = true;
    } else {
      open.back().children.push_back(std::move(done));
    }
  }

  std::string_view text_;
  const std::string& file_;
  size_t pos_ = 0;
};

}  // namespace

XmlDocument scan_xml(std::string_view text, const std::string& file) { return Scanner(text, file).scan(); }

}  // namespace vs
