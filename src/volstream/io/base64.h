// Base64 (RFC 4648, standard alphabet, '=' padding) as VTK's XML files use it.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace vs {

std::string base64_encode(std::string_view bytes);

// Decodes a run of base64 text piece by piece, as VTK's readers do: whitespace is skipped and a
// padded group ("xx==", "xxx=") may end one encoded chunk in mid-stream, because VTK encodes a
// binary header and the data after it separately.
class Base64Reader {
 public:
  // `file` names the input in errors, `what` the array being read.
  Base64Reader(std::string_view text, const std::string& file, std::string what);
  // Exactly n bytes into dst; InputError on a bad character or when the text ends first.
  void read(void* dst, size_t n);
  // At most this many more bytes can be decoded (for checking declared sizes before allocating).
  uint64_t max_remaining() const { return (text_.size() - pos_) / 4 * 3 + pending_size_; }

 private:
  size_t decode_group(uint8_t out[3]);  // the next four characters -> 1..3 bytes
  [[noreturn]] void fail(const std::string& why) const;
  std::string_view text_;
  size_t pos_ = 0;
  uint8_t pending_[3];  // decoded bytes not yet handed out
  size_t pending_begin_ = 0, pending_size_ = 0;
  const std::string& file_;
  std::string what_;
};

}  // namespace vs
