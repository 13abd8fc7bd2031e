// An array on the host that is either its own std::vector or a read-only view of memory kept
// alive by an owner (a dataset file mapped into memory, io/mapped_file.h).
//
// Why views: a dataset's topology is 80 MB per million elements, and reading it into fresh
// memory costs more than reading it: every fresh page is zeroed by the kernel on first touch,
// and on a virtual machine whose free memory is handed back to the host, each first touch also
// faults on the host (bench/RESULTS.md, "Topology mapped, not read"). A mapped file's pages are
// the page cache's own: mapping them costs neither.
//
// Reading is the same for both kinds. Writing (the non-const members) turns a view into an
// owned copy first, so code that builds or edits a mesh works on either; a loaded dataset is
// only read through const references, and a test checks that its arrays stay views.
#pragma once
#include <algorithm>
#include <cstddef>
#include <initializer_list>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace vs {

template <typename T>
class HostArray {
 public:
  using value_type = T;

  HostArray() = default;
  HostArray(std::vector<T> values) : owned_(std::move(values)) {}  // NOLINT: a vector is an array
  HostArray(std::initializer_list<T> values) : owned_(values) {}
  explicit HostArray(size_t count) : owned_(count) {}
  // count values at `data`, which `owner` keeps valid and unchanged while any copy of the view lives.
  static HostArray view(std::shared_ptr<const void> owner, const T* data, size_t count) {
    HostArray a;
    a.owner_ = std::move(owner);
    a.view_ = data;
    a.view_count_ = count;
    return a;
  }

  bool is_view() const { return owner_ != nullptr; }
  const T* data() const { return owner_ ? view_ : owned_.data(); }
  size_t size() const { return owner_ ? view_count_ : owned_.size(); }
  bool empty() const { return size() == 0; }
  const T& operator[](size_t i) const { return data()[i]; }
  const T& at(size_t i) const {
    if (i >= size()) throw std::out_of_range("HostArray::at: " + std::to_string(i) + " of " + std::to_string(size()));
    return data()[i];
  }
  const T* begin() const { return data(); }
  const T* end() const { return data() + size(); }
  const T& front() const { return data()[0]; }
  const T& back() const { return data()[size() - 1]; }
  operator std::span<const T>() const { return {data(), size()}; }  // NOLINT: read as a span
  bool operator==(const HostArray& other) const { return std::ranges::equal(*this, other); }

  // The values as a vector to change (a view is copied into one first).
  std::vector<T>& owned() {
    if (owner_) {
      owned_.assign(view_, view_ + view_count_);
      owner_.reset();
      view_ = nullptr;
      view_count_ = 0;
    }
    return owned_;
  }
  T* data() { return owned().data(); }
  T& operator[](size_t i) { return owned()[i]; }
  T* begin() { return owned().data(); }
  T* end() { return begin() + owned_.size(); }
  T& back() { return owned().back(); }
  void resize(size_t n) { owned().resize(n); }
  void reserve(size_t n) { owned().reserve(n); }
  void clear() { owned().clear(); }
  void push_back(const T& value) { owned().push_back(value); }
  void append(const T* first, const T* last) {
    std::vector<T>& values = owned();
    values.insert(values.end(), first, last);
  }
  template <typename... Args>
  T& emplace_back(Args&&... args) {
    return owned().emplace_back(std::forward<Args>(args)...);
  }

 private:
  std::vector<T> owned_;
  std::shared_ptr<const void> owner_;  // set: a view
  const T* view_ = nullptr;
  size_t view_count_ = 0;
};

}  // namespace vs
