// A whole input file in memory, read front to back as whitespace-separated words and numbers
// (ascii formats) or fixed-size binary values (binary formats, or binary blocks inside a text
// format such as legacy VTK). Every failure is an InputError naming the file, and counts read
// from the file are checked against the bytes left before anything is allocated for them.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "volstream/io/byte_order.h"

namespace vs {

class ParseCursor {
 public:
  explicit ParseCursor(const std::filesystem::path& path);  // reads the whole (regular) file
  ParseCursor(std::string data, std::string file) : data_(std::move(data)), file_(std::move(file)) {}

  const std::string& file() const { return file_; }
  uint64_t size() const { return data_.size(); }
  uint64_t remaining() const { return data_.size() - pos_; }
  uint64_t position() const { return pos_; }
  std::string_view rest() const { return std::string_view(data_).substr(pos_); }  // for parsers of their own
  void seek(uint64_t pos) { pos_ = pos; }
  [[noreturn]] void fail(const std::string& what) const;

  // Text. `what` names the expected item in the error ("point count", "keyword").
  void skip_space();
  std::optional<std::string_view> try_word();
  std::string_view word(const char* what);
  std::string_view line();  // the rest of the current line, without its end; moves past it
  bool at_blank_line();     // only spaces/tabs/CR up to the next newline (or end of file)
  void skip_line() { line(); }
  // Moves past the next occurrence of `text` (a section's end marker); false, and at the end of
  // the file, if there is none.
  bool skip_past(std::string_view text);
  int64_t integer(const char* what);
  double real(const char* what);

  // Binary.
  const char* take(uint64_t bytes, const char* what);
  template <typename T>
  T binary(bool big_endian, const char* what) {
    return load_value<T>(take(sizeof(T), what), big_endian);
  }

  // InputError unless `count` items of at least `min_bytes_each` bytes fit in what is left, so a
  // count read from a damaged file cannot make us allocate more than the file could describe.
  void require_fits(uint64_t count, uint64_t min_bytes_each, const std::string& what) const;

 private:
  std::string data_;
  std::string file_;
  uint64_t pos_ = 0;
};

}  // namespace vs
