#include "volstream/io/base64.h"

#include <cstring>

#include "volstream/core/error.h"

namespace vs {
namespace {

constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

int sextet(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

}  // namespace

std::string base64_encode(std::string_view bytes) {
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t n = std::min<size_t>(3, bytes.size() - i);
    uint32_t group = 0;
    for (size_t k = 0; k < 3; ++k) group = group << 8 | (k < n ? uint8_t(bytes[i + k]) : 0u);
    for (size_t k = 0; k < 4; ++k) out += k <= n ? kAlphabet[(group >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

Base64Reader::Base64Reader(std::string_view text, const std::string& file, std::string what)
    : text_(text), file_(file), what_(std::move(what)) {}

void Base64Reader::fail(const std::string& why) const { input_error(file_, what_ + ": bad base64 data: " + why); }

size_t Base64Reader::decode_group(uint8_t out[3]) {
  char chars[4];
  for (int k = 0; k < 4; ++k) {
    while (pos_ < text_.size() && is_space(text_[pos_])) ++pos_;
    if (pos_ >= text_.size()) fail("the data end too early");
    chars[k] = text_[pos_++];
  }
  // "xx==" carries one byte, "xxx=" two; '=' anywhere else is invalid.
  const size_t padding = chars[3] != '=' ? 0 : chars[2] != '=' ? 1 : 2;
  uint32_t group = 0;
  for (size_t k = 0; k < 4; ++k) {
    const int v = k < 4 - padding ? sextet(chars[k]) : 0;
    if (v < 0) fail("unexpected character '" + std::string(1, chars[k]) + "'");
    group = group << 6 | uint32_t(v);
  }
  for (size_t k = 0; k < 3; ++k) out[k] = uint8_t(group >> (16 - 8 * k));
  return 3 - padding;
}

void Base64Reader::read(void* dst, size_t n) {
  auto* out = static_cast<uint8_t*>(dst);
  while (n > 0) {
    if (pending_size_ == 0) {
      pending_size_ = decode_group(pending_);
      pending_begin_ = 0;
    }
    const size_t take = std::min(n, pending_size_);
    std::memcpy(out, pending_ + pending_begin_, take);
    out += take;
    n -= take;
    pending_begin_ += take;
    pending_size_ -= take;
  }
}

}  // namespace vs
