// qrm/render/image.hpp: a minimal RGB float image, the tiles an image is split into for
// rendering in parts, and the merge that puts the parts back together bit for bit.
//
// Kept deliberately small: qrm::io will provide the library's image type and file formats, and
// this one is meant to be swapped for it.
#pragma once

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace qrm::render {

struct image {
  unsigned width = 0, height = 0;
  std::vector<float> rgb;  // 3 floats per pixel, rows from the top, pixels left to right

  image() = default;
  // A black width x height image.
  image(unsigned w, unsigned h) : width(w), height(h), rgb(std::size_t{3} * w * h, 0.0f) {}

  std::size_t pixels() const { return static_cast<std::size_t>(width) * height; }
  float& at(unsigned x, unsigned y, int channel) { return rgb[index(x, y, channel)]; }
  float at(unsigned x, unsigned y, int channel) const { return rgb[index(x, y, channel)]; }

 private:
  std::size_t index(unsigned x, unsigned y, int channel) const {
    if (x >= width || y >= height || channel < 0 || channel > 2)
      throw std::out_of_range("image: pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") channel " +
                              std::to_string(channel) + " is outside the " + std::to_string(width) + "x" +
                              std::to_string(height) + " image");
    return (static_cast<std::size_t>(y) * width + x) * 3 + static_cast<std::size_t>(channel);
  }
};

// Part `index` of `count` equal shares of an image's pixels (in row-major pixel order).
struct tile {
  unsigned index = 0, count = 1;
};

struct pixel_range {
  std::size_t begin = 0, end = 0;
};

// tile_pixels(pixels, t): pixels [pixels * index / count, pixels * (index + 1) / count).
inline pixel_range tile_pixels(std::size_t pixels, tile t) {
  if (t.count == 0 || t.index >= t.count)
    throw std::invalid_argument("tile: index " + std::to_string(t.index) + " is not below count " +
                                std::to_string(t.count));
  return {pixels * t.index / t.count, pixels * (t.index + 1) / t.count};
}

// merge_tiles(parts): parts[i] rendered as tile {i, parts.size()}; each contributes exactly its
// own pixels, so the result equals the image rendered in one piece, bit for bit.
inline image merge_tiles(const std::vector<image>& parts) {
  if (parts.empty()) throw std::invalid_argument("merge_tiles: no parts");
  image out(parts[0].width, parts[0].height);
  const auto count = static_cast<unsigned>(parts.size());
  for (unsigned i = 0; i < count; ++i) {
    const image& p = parts[i];
    if (p.width != out.width || p.height != out.height || p.rgb.size() != out.rgb.size())
      throw std::invalid_argument("merge_tiles: part " + std::to_string(i) + " is " + std::to_string(p.width) + "x" +
                                  std::to_string(p.height) + ", part 0 is " + std::to_string(out.width) + "x" +
                                  std::to_string(out.height));
    const pixel_range r = tile_pixels(out.pixels(), {i, count});
    for (std::size_t k = 3 * r.begin; k < 3 * r.end; ++k) out.rgb[k] = p.rgb[k];
  }
  return out;
}

// rmse(a, b): root mean square difference over every pixel and channel.
inline double rmse(const image& a, const image& b) {
  if (a.width != b.width || a.height != b.height || a.rgb.size() != b.rgb.size() || a.rgb.empty())
    throw std::invalid_argument("rmse: images must be non-empty and of the same size");
  double sum = 0;
  for (std::size_t k = 0; k < a.rgb.size(); ++k) {
    const double d = static_cast<double>(a.rgb[k]) - static_cast<double>(b.rgb[k]);
    sum += d * d;
  }
  return std::sqrt(sum / static_cast<double>(a.rgb.size()));
}

}  // namespace qrm::render
