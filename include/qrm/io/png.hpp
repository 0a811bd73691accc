// qrm/io/png.hpp: a PNG writer for 8-bit RGB and 8-bit grey images, with no compression library.
//
// Layout of the file: the 8-byte signature; IHDR (bit depth 8, colour type 2 = RGB or 0 = grey,
// no interlace); one IDAT holding a zlib stream (header 0x78 0x01) of *stored* deflate blocks
// (at most 65535 bytes each, BFINAL set on the last one) over the rows, each row prefixed by
// filter byte 0, followed by the Adler-32 of those rows; IEND. Each chunk ends with the CRC-32
// (polynomial 0xEDB88320) of its type and data. Files are larger than compressed PNGs (about 3
// bytes per pixel) but every viewer reads them, and the code stays small and checkable.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "atomic_file.hpp"
#include "image.hpp"

namespace qrm::detail {

inline constexpr std::array<std::uint32_t, 256> crc32_table = [] {
  std::array<std::uint32_t, 256> t{};
  for (std::uint32_t n = 0; n < 256; ++n) {
    std::uint32_t c = n;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    t[n] = c;
  }
  return t;
}();

template <int = 0>
inline void put_be32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(v >> shift));
}

}  // namespace qrm::detail

namespace qrm::io {

// crc32(bytes, previous): the CRC-32 of PNG and zlib (reflected polynomial 0xEDB88320, initial
// and final XOR 0xFFFFFFFF). Passing the CRC of earlier bytes as `previous` continues it, so
// crc32(b, crc32(a)) == crc32(a followed by b).
template <int = 0>
inline std::uint32_t crc32(std::span<const std::uint8_t> bytes, std::uint32_t previous = 0) {
  std::uint32_t c = previous ^ 0xFFFFFFFFu;
  for (std::uint8_t b : bytes) c = detail::crc32_table[(c ^ b) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

// adler32(bytes, previous): the Adler-32 checksum of zlib (sums modulo 65521, starting at 1).
// Passing the checksum of earlier bytes as `previous` continues it.
template <int = 0>
inline std::uint32_t adler32(std::span<const std::uint8_t> bytes, std::uint32_t previous = 1) {
  constexpr std::uint32_t mod = 65521;
  // 5552 is the largest n for which 255 n (n + 1) / 2 + (n + 1) (mod - 1) fits in 32 bits, so the
  // sums may run that long before reducing.
  constexpr std::size_t block = 5552;
  std::uint32_t a = previous & 0xFFFFu, b = previous >> 16;
  for (std::size_t start = 0; start < bytes.size(); start += block) {
    const std::size_t end = std::min(bytes.size(), start + block);
    for (std::size_t k = start; k < end; ++k) {
      a += bytes[k];
      b += a;
    }
    a %= mod;
    b %= mod;
  }
  return (b << 16) | a;
}

// encode_png(img): the bytes of the PNG file for an 8-bit image (channels 1 or 3). Throws
// std::invalid_argument naming the problem for a zero or too large size, another channel count,
// or a data size that does not match width x height x channels.
template <int = 0>
std::vector<std::uint8_t> encode_png(const image8& img) {
  constexpr std::size_t png_max = 0x7FFFFFFF;  // PNG's limit on sizes and chunk lengths
  if (img.width == 0 || img.height == 0 || img.width > png_max || img.height > png_max)
    throw std::invalid_argument("encode_png: size " + detail::size_text(img.width, img.height) +
                                " is not in 1..2147483647 per side");
  if (img.channels != 1 && img.channels != 3)
    throw std::invalid_argument("encode_png: " + std::to_string(img.channels) +
                                " channels (only 1 = grey and 3 = RGB are written)");
  const std::size_t row = img.width * img.channels;
  if (img.height > (png_max - 64) / (row + 1))
    throw std::invalid_argument("encode_png: size " + detail::size_text(img.width, img.height) +
                                " does not fit in one PNG chunk");
  if (img.data.size() != row * img.height)
    throw std::invalid_argument("encode_png: " + std::to_string(img.data.size()) + " bytes of pixels for a " +
                                detail::size_text(img.width, img.height) + "x" + std::to_string(img.channels) +
                                " image, which needs " + std::to_string(row * img.height));

  // The filtered rows (what the zlib stream carries).
  std::vector<std::uint8_t> raw;
  raw.reserve((row + 1) * img.height);
  for (std::size_t y = 0; y < img.height; ++y) {
    raw.push_back(0);  // filter type 0: the row's bytes as they are
    raw.insert(raw.end(), img.data.begin() + static_cast<std::ptrdiff_t>(y * row),
               img.data.begin() + static_cast<std::ptrdiff_t>((y + 1) * row));
  }

  // zlib: CMF 0x78 (deflate, 32K window), FLG 0x01 (no dictionary, level 0, 0x7801 % 31 == 0).
  constexpr std::size_t max_block = 65535;
  const std::size_t blocks = (raw.size() + max_block - 1) / max_block;
  std::vector<std::uint8_t> z;
  z.reserve(raw.size() + 5 * blocks + 6);
  z.push_back(0x78);
  z.push_back(0x01);
  for (std::size_t k = 0; k < blocks; ++k) {
    const std::size_t start = k * max_block;
    const std::size_t len = std::min(max_block, raw.size() - start);
    z.push_back(k + 1 == blocks ? 0x01 : 0x00);  // BFINAL bit, BTYPE 00 (stored), then pad to a byte
    const auto len16 = static_cast<std::uint16_t>(len);
    const auto nlen16 = static_cast<std::uint16_t>(~len16);
    z.push_back(static_cast<std::uint8_t>(len16 & 0xFF));
    z.push_back(static_cast<std::uint8_t>(len16 >> 8));
    z.push_back(static_cast<std::uint8_t>(nlen16 & 0xFF));
    z.push_back(static_cast<std::uint8_t>(nlen16 >> 8));
    z.insert(z.end(), raw.begin() + static_cast<std::ptrdiff_t>(start),
             raw.begin() + static_cast<std::ptrdiff_t>(start + len));
  }
  detail::put_be32(z, adler32(raw));

  std::vector<std::uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  auto chunk = [&out](const char (&type)[5], std::span<const std::uint8_t> data) {
    detail::put_be32(out, static_cast<std::uint32_t>(data.size()));
    const std::size_t type_at = out.size();
    out.insert(out.end(), type, type + 4);
    out.insert(out.end(), data.begin(), data.end());
    detail::put_be32(out, crc32(std::span<const std::uint8_t>(out).subspan(type_at, 4 + data.size())));
  };
  std::vector<std::uint8_t> ihdr;
  detail::put_be32(ihdr, static_cast<std::uint32_t>(img.width));
  detail::put_be32(ihdr, static_cast<std::uint32_t>(img.height));
  ihdr.insert(ihdr.end(), {8, static_cast<std::uint8_t>(img.channels == 3 ? 2 : 0), 0, 0, 0});
  chunk("IHDR", ihdr);
  chunk("IDAT", z);
  chunk("IEND", {});
  return out;
}

// write_png(path, img): writes an 8-bit image as a PNG, atomically (see atomic_file.hpp).
template <int = 0>
void write_png(const std::filesystem::path& path, const image8& img) {
  const std::vector<std::uint8_t> bytes = encode_png(img);
  write_file_atomically(path, [&bytes](file_sink& out) { out.write(bytes.data(), bytes.size()); });
}

// write_png(path, img, tm): tone maps a linear image to 8-bit sRGB (to_srgb8, which rejects
// NaN/infinite pixels by name) and writes it as a PNG.
template <int = 0>
void write_png(const std::filesystem::path& path, const image& img, tone_map tm = {}) {
  write_png(path, to_srgb8(img, tm));
}

}  // namespace qrm::io

// This header's part of <qrm/io/compiled_io.hpp> (QRM_COMPILED_IO).
#define QRM_DETAIL_PNG_INSTANCES(PREFIX)                                          \
  PREFIX std::vector<std::uint8_t> encode_png<0>(const image8&);                  \
  PREFIX void write_png<0>(const std::filesystem::path&, const image8&);          \
  PREFIX void write_png<0>(const std::filesystem::path&, const image&, tone_map);
#ifdef QRM_COMPILED_IO
namespace qrm::io {
QRM_DETAIL_PNG_INSTANCES(extern template)
}  // namespace qrm::io
#endif
