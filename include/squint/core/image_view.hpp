// Non-owning views of 8-bit grey images, used by the allocation-free glance kernels.
#pragma once

#include <cstddef>
#include <cstdint>

namespace squint {

struct GrayView {
  const std::uint8_t* data = nullptr;
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride = 0;  // bytes between rows

  const std::uint8_t* Row(int v) const { return data + v * stride; }
  std::uint8_t At(int u, int v) const { return data[v * stride + u]; }
  bool Empty() const { return data == nullptr || width <= 0 || height <= 0; }
};

struct MutableGrayView {
  std::uint8_t* data = nullptr;
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride = 0;

  std::uint8_t* Row(int v) const { return data + v * stride; }
  std::uint8_t& At(int u, int v) const { return data[v * stride + u]; }
  operator GrayView() const { return {data, width, height, stride}; }
};

}  // namespace squint
