// qrm/io/image.hpp: linear-RGB float images and what the renderer does with them before
// writing: tone mapping to 8-bit sRGB, bilinear and nearest upsampling, differences, a
// false-colour ramp for error images, side-by-side panels, and statistics.
//
// Conventions: pixel (x, y) has x = column (0 = left), y = row (0 = top); pixels are stored row
// by row from the top. Values are linear radiance (not gamma encoded).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace qrm::io {

// rgb: one linear-RGB pixel.
struct rgb {
  float r = 0, g = 0, b = 0;
  // channel(c): r, g or b for c = 0, 1, 2.
  float& channel(int c) { return c == 0 ? r : c == 1 ? g : b; }
  float channel(int c) const { return c == 0 ? r : c == 1 ? g : b; }
  friend bool operator==(const rgb&, const rgb&) = default;
};

}  // namespace qrm::io

namespace qrm::detail {

template <int = 0>
inline std::string size_text(std::size_t w, std::size_t h) { return std::to_string(w) + "x" + std::to_string(h); }

template <int = 0>
inline std::string float_text(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

}  // namespace qrm::detail

namespace qrm::io {

// image: width x height linear-RGB pixels (an image with no pixels has width = height = 0).
class image {
 public:
  image() = default;
  // image(width, height, fill): every pixel set to `fill`; width and height both zero or both
  // positive.
  template <int = 0>
  image(std::size_t width, std::size_t height, rgb fill = {}) : width_(width), height_(height) {
    if ((width == 0) != (height == 0))
      throw std::invalid_argument("image: size " + detail::size_text(width, height) +
                                  " has one zero side (use 0x0 for an empty image)");
    if (width != 0 && height > std::numeric_limits<std::size_t>::max() / 3 / width)
      throw std::length_error("image: size " + detail::size_text(width, height) + " is too large");
    pixels_.assign(width * height, fill);
  }

  std::size_t width() const { return width_; }
  std::size_t height() const { return height_; }
  bool empty() const { return pixels_.empty(); }

  // at(x, y): the pixel in column x, row y; std::out_of_range naming (x, y) and the size.
  rgb& at(std::size_t x, std::size_t y) { return pixels_[index(x, y)]; }
  const rgb& at(std::size_t x, std::size_t y) const { return pixels_[index(x, y)]; }

  // pixels(): all pixels, row by row from the top.
  std::span<rgb> pixels() { return {pixels_.data(), pixels_.size()}; }
  std::span<const rgb> pixels() const { return {pixels_.data(), pixels_.size()}; }

  friend bool operator==(const image&, const image&) = default;

 private:
  template <int = 0>
  std::size_t index(std::size_t x, std::size_t y) const {
    if (x >= width_ || y >= height_)
      throw std::out_of_range("image::at: pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                              ") is outside the " + detail::size_text(width_, height_) + " image");
    return y * width_ + x;
  }
  std::size_t width_ = 0, height_ = 0;
  std::vector<rgb> pixels_;
};

// image8: 8-bit pixels ready for a file: `channels` (1 = grey, 3 = RGB) bytes per pixel, rows
// from the top, no padding.
struct image8 {
  std::size_t width = 0, height = 0, channels = 3;
  std::vector<std::uint8_t> data;
};

// transfer_curve: how linear values become display values.
enum class transfer_curve {
  srgb,     // the IEC 61966-2-1 sRGB curve (linear toe below 0.0031308, then 1.055 v^(1/2.4) - 0.055)
  gamma22,  // a pure power law v^(1/2.2)
};

// tone_map: display value = curve(clamp(exposure * linear, 0, 1)), then rounded to the nearest
// of 0..255. Negative values (noisy estimates) become 0 and values above 1/exposure become 255.
struct tone_map {
  float exposure = 1.0f;
  transfer_curve curve = transfer_curve::srgb;
};

}  // namespace qrm::io

namespace qrm::detail {

template <int = 0>
inline const char* channel_name(int c) { return c == 0 ? "R" : c == 1 ? "G" : "B"; }

// Throws std::invalid_argument naming the first pixel and channel that is NaN or infinite.
template <int = 0>
inline void require_finite(const io::image& img, const char* who) {
  for (std::size_t y = 0; y < img.height(); ++y)
    for (std::size_t x = 0; x < img.width(); ++x) {
      const io::rgb& p = img.pixels()[y * img.width() + x];
      const float v[3] = {p.r, p.g, p.b};
      for (int c = 0; c < 3; ++c)
        if (!std::isfinite(v[c]))
          throw std::invalid_argument(std::string(who) + ": pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                      ") channel " + channel_name(c) + " is " + float_text(v[c]) +
                                      " (only finite values can be shown)");
    }
}

template <int = 0>
inline void require_same_size(const io::image& a, const io::image& b, const char* who) {
  if (a.width() != b.width() || a.height() != b.height())
    throw std::invalid_argument(std::string(who) + ": image sizes differ (" + size_text(a.width(), a.height()) +
                                " vs " + size_text(b.width(), b.height()) + ")");
}

template <int = 0>
inline void require_nonempty(const io::image& img, const char* who) {
  if (img.empty()) throw std::invalid_argument(std::string(who) + ": the image is empty (0x0)");
}

// A position along one axis of the output, in source cell-centre coordinates, as the exact
// rational ((2 i + 1) n_in - n_out) / (2 n_out): integer part `lo` and fraction num/den. Kept
// exact so that output pixels whose centres fall on source cell centres get exactly the cell's
// value (fraction 0).
struct bilinear_tap {
  std::size_t lo, hi;
  double t;  // weight of `hi`
};
template <int = 0>
inline bilinear_tap bilinear_position(std::size_t i, std::size_t n_in, std::size_t n_out) {
  const long long num = static_cast<long long>((2 * i + 1) * n_in) - static_cast<long long>(n_out);
  const long long den = static_cast<long long>(2 * n_out);
  if (num <= 0) return {0, 0, 0.0};  // left of (or at) the first cell centre: edge value
  const auto lo = static_cast<std::size_t>(num / den);
  if (lo >= n_in - 1) return {n_in - 1, n_in - 1, 0.0};  // at or right of the last centre
  return {lo, lo + 1, static_cast<double>(num % den) / static_cast<double>(den)};
}

template <int = 0>
inline void require_output_size(std::size_t w, std::size_t h, const char* who) {
  if (w == 0 || h == 0)
    throw std::invalid_argument(std::string(who) + ": output size " + size_text(w, h) + " must be positive");
}

}  // namespace qrm::detail

namespace qrm::io {

// encode_display(v, curve): the display value in [0, 1] of a linear value v already clamped to
// [0, 1].
template <int = 0>
inline double encode_display(double v, transfer_curve curve) {
  if (curve == transfer_curve::gamma22) return std::pow(v, 1.0 / 2.2);
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

// decode_display(d, curve): the inverse of encode_display, for d in [0, 1].
template <int = 0>
inline double decode_display(double d, transfer_curve curve) {
  if (curve == transfer_curve::gamma22) return std::pow(d, 2.2);
  return d <= 0.04045 ? d / 12.92 : std::pow((d + 0.055) / 1.055, 2.4);
}

// to_8bit(linear, tm): one channel through the tone map (see tone_map); std::invalid_argument if
// `linear` is NaN or infinite or the exposure is not finite and positive.
template <int = 0>
inline std::uint8_t to_8bit(float linear, tone_map tm = {}) {
  if (!std::isfinite(linear) || !(std::isfinite(tm.exposure) && tm.exposure > 0))
    throw std::invalid_argument("to_8bit: value " + detail::float_text(linear) + " with exposure " +
                                detail::float_text(tm.exposure) + " (both must be finite, the exposure positive)");
  double v = static_cast<double>(linear) * static_cast<double>(tm.exposure);
  v = std::clamp(v, 0.0, 1.0);
  return static_cast<std::uint8_t>(std::floor(encode_display(v, tm.curve) * 255.0 + 0.5));
}

// to_srgb8(img, tm): the 8-bit RGB image to write; std::invalid_argument for an empty image, an
// exposure that is not finite and positive, or a NaN/infinite pixel (named).
template <int = 0>
inline image8 to_srgb8(const image& img, tone_map tm = {}) {
  detail::require_nonempty(img, "to_srgb8");
  if (!(std::isfinite(tm.exposure) && tm.exposure > 0))
    throw std::invalid_argument("to_srgb8: exposure " + detail::float_text(tm.exposure) +
                                " must be finite and positive");
  detail::require_finite(img, "to_srgb8");
  image8 out{img.width(), img.height(), 3, {}};
  out.data.reserve(img.pixels().size() * 3);
  for (const rgb& p : img.pixels()) {
    out.data.push_back(to_8bit(p.r, tm));
    out.data.push_back(to_8bit(p.g, tm));
    out.data.push_back(to_8bit(p.b, tm));
  }
  return out;
}

// upsample_bilinear(src, width, height): resamples `src` bilinearly, treating each source value
// as a sample at its cell centre. Output pixel i (centre i + 1/2 of `width`) reads source
// coordinate u = (i + 1/2) * src.width() / width - 1/2, where cell c's centre is at u = c, and
// interpolates linearly between the two nearest centres (likewise in y). Outside the outermost
// centres (the half cell at each border) the value is held constant at the edge cell's value
// (clamp to edge). With an odd integer scale factor k, output pixel k c + (k - 1)/2 lies exactly
// on the centre of cell c and gets exactly its value.
template <int = 0>
inline image upsample_bilinear(const image& src, std::size_t width, std::size_t height) {
  detail::require_nonempty(src, "upsample_bilinear");
  detail::require_output_size(width, height, "upsample_bilinear");
  std::vector<detail::bilinear_tap> xs(width), ys(height);
  for (std::size_t i = 0; i < width; ++i) xs[i] = detail::bilinear_position(i, src.width(), width);
  for (std::size_t j = 0; j < height; ++j) ys[j] = detail::bilinear_position(j, src.height(), height);
  image out(width, height);
  auto px = [&](std::size_t x, std::size_t y) -> const rgb& { return src.pixels()[y * src.width() + x]; };
  auto lerp = [](double a, double b, double t) { return t == 0.0 ? a : a + (b - a) * t; };
  for (std::size_t j = 0; j < height; ++j)
    for (std::size_t i = 0; i < width; ++i) {
      const auto& tx = xs[i];
      const auto& ty = ys[j];
      const rgb &p00 = px(tx.lo, ty.lo), &p10 = px(tx.hi, ty.lo), &p01 = px(tx.lo, ty.hi), &p11 = px(tx.hi, ty.hi);
      auto channel = [&](float rgb::*c) {
        const double top = lerp(p00.*c, p10.*c, tx.t), bottom = lerp(p01.*c, p11.*c, tx.t);
        return static_cast<float>(lerp(top, bottom, ty.t));
      };
      out.pixels()[j * width + i] = {channel(&rgb::r), channel(&rgb::g), channel(&rgb::b)};
    }
  return out;
}

// upsample_bilinear(src, factor): the same with width and height multiplied by `factor`.
template <int = 0>
inline image upsample_bilinear(const image& src, std::size_t factor) {
  return upsample_bilinear(src, src.width() * factor, src.height() * factor);
}

// upsample_nearest(src, width, height): each output pixel takes the source cell its centre falls
// in (cell floor((i + 1/2) * src.width() / width)); with an integer factor every cell becomes a
// factor x factor block.
template <int = 0>
inline image upsample_nearest(const image& src, std::size_t width, std::size_t height) {
  detail::require_nonempty(src, "upsample_nearest");
  detail::require_output_size(width, height, "upsample_nearest");
  image out(width, height);
  for (std::size_t j = 0; j < height; ++j) {
    const std::size_t sy = (2 * j + 1) * src.height() / (2 * height);
    for (std::size_t i = 0; i < width; ++i) {
      const std::size_t sx = (2 * i + 1) * src.width() / (2 * width);
      out.pixels()[j * width + i] = src.pixels()[sy * src.width() + sx];
    }
  }
  return out;
}

// upsample_nearest(src, factor): the same with width and height multiplied by `factor`.
template <int = 0>
inline image upsample_nearest(const image& src, std::size_t factor) {
  return upsample_nearest(src, src.width() * factor, src.height() * factor);
}

// absolute_difference(a, b): per channel |a - b|; std::invalid_argument if the sizes differ.
template <int = 0>
inline image absolute_difference(const image& a, const image& b) {
  detail::require_same_size(a, b, "absolute_difference");
  image out(a.width(), a.height());
  for (std::size_t k = 0; k < a.pixels().size(); ++k) {
    const rgb &p = a.pixels()[k], &q = b.pixels()[k];
    out.pixels()[k] = {std::fabs(p.r - q.r), std::fabs(p.g - q.g), std::fabs(p.b - q.b)};
  }
  return out;
}

// error_ramp(t): the false-colour ramp for t in [0, 1] (clamped), as linear RGB. It is defined by
// five display (sRGB-encoded) colours at t = 0, 1/4, 1/2, 3/4, 1:
//   black (0, 0, 0), indigo (0.25, 0, 0.55), crimson (0.80, 0.15, 0.35), orange (1, 0.6, 0),
//   pale yellow (1, 1, 0.75),
// interpolated linearly in display space and returned decoded to linear, so that to_srgb8 with
// exposure 1 shows the display colours. Display luminance rises strictly from black to pale
// yellow, so brighter always means larger error, also in grey-scale print.
// NaN is std::invalid_argument.
template <int = 0>
inline rgb error_ramp(float t) {
  if (std::isnan(t)) throw std::invalid_argument("error_ramp: t is nan");
  static constexpr float stops[5][3] = {
      {0.0f, 0.0f, 0.0f}, {0.25f, 0.0f, 0.55f}, {0.80f, 0.15f, 0.35f}, {1.0f, 0.6f, 0.0f}, {1.0f, 1.0f, 0.75f}};
  const double s = std::clamp(static_cast<double>(t), 0.0, 1.0) * 4.0;
  const int k = std::min(3, static_cast<int>(s));
  const double f = s - k;
  double d[3];
  for (int c = 0; c < 3; ++c) d[c] = stops[k][c] + (stops[k + 1][c] - stops[k][c]) * f;
  auto lin = [](double v) { return static_cast<float>(decode_display(v, transfer_curve::srgb)); };
  return {lin(d[0]), lin(d[1]), lin(d[2])};
}

// false_colour(err, max_value): each pixel's error (the mean of its three channels) mapped
// through error_ramp(error / max_value). max_value must be finite and positive; NaN/infinite
// pixels are an error (named).
template <int = 0>
inline image false_colour(const image& err, float max_value) {
  detail::require_nonempty(err, "false_colour");
  if (!(std::isfinite(max_value) && max_value > 0))
    throw std::invalid_argument("false_colour: max_value " + detail::float_text(max_value) +
                                " must be finite and positive");
  detail::require_finite(err, "false_colour");
  image out(err.width(), err.height());
  for (std::size_t k = 0; k < err.pixels().size(); ++k) {
    const rgb& p = err.pixels()[k];
    const double mean = (static_cast<double>(p.r) + p.g + p.b) / 3.0;
    out.pixels()[k] = error_ramp(static_cast<float>(mean / max_value));
  }
  return out;
}

// false_colour(err): the same scaled to the largest pixel error (all-zero maps to black).
template <int = 0>
inline image false_colour(const image& err) {
  detail::require_nonempty(err, "false_colour");
  detail::require_finite(err, "false_colour");
  double largest = 0;
  for (const rgb& p : err.pixels()) largest = std::max(largest, (static_cast<double>(p.r) + p.g + p.b) / 3.0);
  return false_colour(err, largest > 0 ? static_cast<float>(largest) : 1.0f);
}

// side_by_side(panels, gap, background): the panels left to right with `gap` background pixels
// between them; the result is as tall as the tallest panel and a shorter panel of height h starts
// at row (height - h) / 2 (rounded down), i.e. centred. std::invalid_argument if there is no panel or a panel is empty.
template <int = 0>
inline image side_by_side(std::span<const image> panels, std::size_t gap = 4, rgb background = {1, 1, 1}) {
  if (panels.empty()) throw std::invalid_argument("side_by_side: no panels");
  std::size_t width = 0, height = 0;
  for (std::size_t k = 0; k < panels.size(); ++k) {
    if (panels[k].empty()) throw std::invalid_argument("side_by_side: panel " + std::to_string(k) + " is empty");
    width += panels[k].width() + (k ? gap : 0);
    height = std::max(height, panels[k].height());
  }
  image out(width, height, background);
  std::size_t x0 = 0;
  for (const image& p : panels) {
    const std::size_t y0 = (height - p.height()) / 2;
    for (std::size_t y = 0; y < p.height(); ++y)
      std::copy_n(p.pixels().begin() + static_cast<std::ptrdiff_t>(y * p.width()), p.width(),
                  out.pixels().begin() + static_cast<std::ptrdiff_t>((y0 + y) * width + x0));
    x0 += p.width() + gap;
  }
  return out;
}

// side_by_side(a, b, gap, background): two panels.
template <int = 0>
inline image side_by_side(const image& a, const image& b, std::size_t gap = 4, rgb background = {1, 1, 1}) {
  const image both[2] = {a, b};
  return side_by_side(std::span<const image>(both), gap, background);
}

// image_stats: over every channel of every pixel.
struct image_stats {
  float min = 0, max = 0;
  double mean = 0;
};

// stats(img): smallest, largest and mean channel value; NaN/infinite pixels are an error.
template <int = 0>
inline image_stats stats(const image& img) {
  detail::require_nonempty(img, "stats");
  detail::require_finite(img, "stats");
  image_stats s{std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(), 0.0};
  double sum = 0;
  for (const rgb& p : img.pixels())
    for (float v : {p.r, p.g, p.b}) {
      s.min = std::min(s.min, v);
      s.max = std::max(s.max, v);
      sum += v;
    }
  s.mean = sum / (3.0 * static_cast<double>(img.pixels().size()));
  return s;
}

// rmse(a, b): sqrt(mean over every channel of every pixel of (a - b)^2); sizes must match and
// values be finite.
template <int = 0>
inline double rmse(const image& a, const image& b) {
  detail::require_same_size(a, b, "rmse");
  detail::require_nonempty(a, "rmse");
  detail::require_finite(a, "rmse");
  detail::require_finite(b, "rmse");
  double sum = 0;
  for (std::size_t k = 0; k < a.pixels().size(); ++k) {
    const rgb &p = a.pixels()[k], &q = b.pixels()[k];
    for (double d : {static_cast<double>(p.r) - q.r, static_cast<double>(p.g) - q.g, static_cast<double>(p.b) - q.b})
      sum += d * d;
  }
  return std::sqrt(sum / (3.0 * static_cast<double>(a.pixels().size())));
}

}  // namespace qrm::io
