// qrm/render/tiles.hpp: the tiles an image is split into for rendering in parts (e.g. a job
// array on a cluster), and the merge that puts the parts back together bit for bit.
#pragma once

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "../io/image.hpp"

namespace qrm::render {

// The renderer's images are the library's linear-RGB images.
using image = io::image;

// Part `index` of `count` equal shares of an image's pixels (in row-major pixel order).
struct tile {
  unsigned index = 0, count = 1;
};

struct pixel_range {
  std::size_t begin = 0, end = 0;
};

// tile_pixels(pixels, t): pixels [pixels * index / count, pixels * (index + 1) / count).
template <int = 0>
inline pixel_range tile_pixels(std::size_t pixels, tile t) {
  if (t.count == 0 || t.index >= t.count)
    throw std::invalid_argument("tile: index " + std::to_string(t.index) + " is not below count " +
                                std::to_string(t.count));
  return {pixels * t.index / t.count, pixels * (t.index + 1) / t.count};
}

// merge_tiles(parts): parts[i] rendered as tile {i, parts.size()}; each contributes exactly its
// own pixels, so the result equals the image rendered in one piece, bit for bit.
template <int = 0>
inline image merge_tiles(const std::vector<image>& parts) {
  if (parts.empty()) throw std::invalid_argument("merge_tiles: no parts");
  image out(parts[0].width(), parts[0].height());
  const auto count = static_cast<unsigned>(parts.size());
  for (unsigned i = 0; i < count; ++i) {
    const image& p = parts[i];
    if (p.width() != out.width() || p.height() != out.height())
      throw std::invalid_argument("merge_tiles: part " + std::to_string(i) + " is " + std::to_string(p.width()) + "x" +
                                  std::to_string(p.height()) + ", part 0 is " + std::to_string(out.width()) + "x" +
                                  std::to_string(out.height()));
    const pixel_range r = tile_pixels(out.pixels().size(), {i, count});
    for (std::size_t k = r.begin; k < r.end; ++k) out.pixels()[k] = p.pixels()[k];
  }
  return out;
}

}  // namespace qrm::render
