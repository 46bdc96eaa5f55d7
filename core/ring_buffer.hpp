// Fixed-capacity ring: the fuser's IMU history and the trajectory keep the
// last few seconds without growing and without allocating after construction.
// Pushing into a full ring overwrites the oldest element.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <vector>

namespace tumble {

template <typename T>
class RingBuffer {
 public:
  explicit RingBuffer(std::size_t capacity) : storage_(capacity) {
    if (capacity == 0) throw std::invalid_argument("RingBuffer: capacity must be positive");
  }

  void push_back(const T& value) {
    if (size_ == storage_.size()) {
      storage_[head_] = value;
      head_ = (head_ + 1) % storage_.size();
    } else {
      (*this)[size_++] = value;
    }
  }
  void pop_back() { --size_; }
  void pop_front() {
    head_ = (head_ + 1) % storage_.size();
    --size_;
  }
  void clear() { head_ = size_ = 0; }

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  std::size_t capacity() const { return storage_.size(); }
  // 0 = oldest.
  const T& operator[](std::size_t i) const { return storage_[(head_ + i) % storage_.size()]; }
  T& operator[](std::size_t i) { return storage_[(head_ + i) % storage_.size()]; }
  const T& front() const { return (*this)[0]; }
  const T& back() const { return (*this)[size_ - 1]; }
  T& back() { return (*this)[size_ - 1]; }

 private:
  std::vector<T> storage_;
  std::size_t head_ = 0;
  std::size_t size_ = 0;
};

}  // namespace tumble
