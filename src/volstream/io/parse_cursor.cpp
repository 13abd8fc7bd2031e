#include "volstream/io/parse_cursor.h"

#include <cctype>
#include <charconv>

#include "volstream/core/error.h"
#include "volstream/io/binary_file.h"

namespace vs {

namespace {
bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }
std::string quoted(std::string_view w) {
  constexpr size_t kMax = 40;  // a binary blob read as a word should not flood the message
  std::string s(w.substr(0, kMax));
  for (char& c : s)
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  return "'" + s + (w.size() > kMax ? "...'" : "'");
}
}  // namespace

ParseCursor::ParseCursor(const std::filesystem::path& path) : file_(path.string()) {
  const uint64_t size = file_size_checked(path);
  data_.resize(size);
  read_exact(path, 0, data_.data(), size);
}

void ParseCursor::fail(const std::string& what) const { input_error(file_, what); }

void ParseCursor::skip_space() {
  while (pos_ < data_.size() && is_space(data_[pos_])) ++pos_;
}

std::optional<std::string_view> ParseCursor::try_word() {
  skip_space();
  if (pos_ >= data_.size()) return std::nullopt;
  const uint64_t start = pos_;
  while (pos_ < data_.size() && !is_space(data_[pos_])) ++pos_;
  return std::string_view(data_).substr(start, pos_ - start);
}

std::string_view ParseCursor::word(const char* what) {
  const auto w = try_word();
  if (!w) fail(std::string("unexpected end of file, expected ") + what);
  return *w;
}

std::string_view ParseCursor::line() {
  const uint64_t start = pos_;
  const size_t end = data_.find('\n', pos_);
  pos_ = end == std::string::npos ? data_.size() : end + 1;
  std::string_view l = std::string_view(data_).substr(start, (end == std::string::npos ? data_.size() : end) - start);
  if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
  return l;
}

bool ParseCursor::skip_past(std::string_view text) {
  const size_t at = data_.find(text, pos_);
  pos_ = at == std::string::npos ? data_.size() : at + text.size();
  return at != std::string::npos;
}

bool ParseCursor::at_blank_line() {
  for (uint64_t i = pos_; i < data_.size() && data_[i] != '\n'; ++i)
    if (!is_space(data_[i])) return false;
  return true;
}

int64_t ParseCursor::integer(const char* what) {
  const std::string_view w = word(what);
  int64_t v = 0;
  const char* first = w.data() + (w.size() > 1 && w[0] == '+' ? 1 : 0);
  const auto [end, ec] = std::from_chars(first, w.data() + w.size(), v);
  if (ec != std::errc() || end != w.data() + w.size())
    fail("expected an integer (" + std::string(what) + "), found " + quoted(w));
  return v;
}

double ParseCursor::real(const char* what) {
  const std::string_view w = word(what);
  double v = 0;
  const char* first = w.data() + (w.size() > 1 && w[0] == '+' ? 1 : 0);
  const auto [end, ec] = std::from_chars(first, w.data() + w.size(), v);
  // Out-of-range values (1e999) are errors too: check_mesh would refuse the infinity anyway.
  if (ec != std::errc() || end != w.data() + w.size())
    fail("expected a number (" + std::string(what) + "), found " + quoted(w));
  return v;
}

const char* ParseCursor::take(uint64_t bytes, const char* what) {
  if (bytes > remaining())
    fail(std::string("truncated: ") + what + " needs " + std::to_string(bytes) + " bytes at offset " +
         std::to_string(pos_) + ", " + std::to_string(remaining()) + " left");
  const char* p = data_.data() + pos_;
  pos_ += bytes;
  return p;
}

void ParseCursor::require_fits(uint64_t count, uint64_t min_bytes_each, const std::string& what) const {
  if (min_bytes_each && count > remaining() / min_bytes_each)
    fail(what + ": " + std::to_string(count) + " items cannot fit in the " + std::to_string(remaining()) +
         " bytes left of the file");
}

}  // namespace vs
