// qrm/io/pfm.hpp: PFM (portable float map) files, for linear values that must survive exactly.
//
// Format: the text header "PF\n<width> <height>\n<scale>\n" ("Pf" for one grey channel), then
// width x height pixels of 32-bit IEEE floats, rows from the *bottom* of the image to the top.
// A negative scale means little-endian floats, a positive one big-endian; |scale| carries no
// meaning here. We write "PF", scale -1.0, little-endian, and every float bit for bit (NaN and
// infinities included: this format is for exact dumps, not for display). The reader accepts PF
// and Pf (grey is copied into R, G and B) in either byte order.
#pragma once

#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "atomic_file.hpp"
#include "image.hpp"

namespace qrm::detail {

template <int = 0>
inline void put_le32(std::vector<std::uint8_t>& out, float v) {
  const auto u = std::bit_cast<std::uint32_t>(v);
  for (int shift = 0; shift < 32; shift += 8) out.push_back(static_cast<std::uint8_t>(u >> shift));
}

template <int = 0>
inline std::vector<std::uint8_t> read_whole_file(const std::filesystem::path& path, const char* who) {
  errno = 0;
  std::FILE* f = std::fopen(path.string().c_str(), "rb");
  if (f == nullptr)
    throw std::runtime_error(std::string(who) + ": cannot open '" + path.string() + "': " + errno_text(errno));
  std::vector<std::uint8_t> bytes;
  std::uint8_t buf[65536];
  for (;;) {
    const std::size_t n = std::fread(buf, 1, sizeof buf, f);
    bytes.insert(bytes.end(), buf, buf + n);
    if (n < sizeof buf) break;
  }
  const bool failed = std::ferror(f) != 0;
  const int err = errno;
  std::fclose(f);
  if (failed) throw std::runtime_error(std::string(who) + ": cannot read '" + path.string() + "': " + errno_text(err));
  return bytes;
}

// Printable rendering of a header token for error messages.
template <int = 0>
inline std::string quoted_token(std::string_view s) {
  std::string r = "'";
  for (char c : s.substr(0, 40)) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7F) {
      r += c;
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", u);
      r += hex;
    }
  }
  return r + (s.size() > 40 ? "...'" : "'");
}

}  // namespace qrm::detail

namespace qrm::io {

// write_pfm(path, img): writes a colour PFM (little-endian, rows bottom to top) atomically.
template <int = 0>
void write_pfm(const std::filesystem::path& path, const image& img) {
  detail::require_nonempty(img, "write_pfm");
  const std::string header = "PF\n" + std::to_string(img.width()) + " " + std::to_string(img.height()) + "\n-1.0\n";
  write_file_atomically(path, [&](file_sink& out) {
    out.write(header);
    std::vector<std::uint8_t> row;
    row.reserve(img.width() * 12);
    for (std::size_t y = img.height(); y-- > 0;) {
      row.clear();
      for (std::size_t x = 0; x < img.width(); ++x) {
        const rgb& p = img.pixels()[y * img.width() + x];
        detail::put_le32(row, p.r);
        detail::put_le32(row, p.g);
        detail::put_le32(row, p.b);
      }
      out.write(row.data(), row.size());
    }
  });
}

// parse_pfm(bytes, name): the image in a PFM file's bytes; std::invalid_argument naming `name`
// and the problem for a bad magic, size, scale, or a pixel data length that does not match.
template <int = 0>
image parse_pfm(std::span<const std::uint8_t> bytes, const std::string& name = "PFM data") {
  const std::string who = "read_pfm: '" + name + "'";
  std::size_t pos = 0;
  auto is_space = [](std::uint8_t c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
  // The next whitespace-separated header token.
  auto token = [&](const char* what) {
    while (pos < bytes.size() && is_space(bytes[pos])) ++pos;
    const std::size_t start = pos;
    while (pos < bytes.size() && !is_space(bytes[pos]) && pos - start < 64) ++pos;
    if (start == pos) throw std::invalid_argument(who + ": the header ends before the " + std::string(what));
    return std::string_view(reinterpret_cast<const char*>(bytes.data()) + start, pos - start);
  };
  const std::string_view magic = token("magic number");
  std::size_t channels = 0;
  if (magic == "PF") {
    channels = 3;
  } else if (magic == "Pf") {
    channels = 1;
  } else {
    throw std::invalid_argument(who + ": not a PFM file (magic " + detail::quoted_token(magic) +
                                ", expected 'PF' or 'Pf')");
  }
  auto dimension = [&](const char* what) {
    const std::string_view t = token(what);
    std::size_t v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || end != t.data() + t.size() || v == 0 || v > 0x7FFFFFFF)
      throw std::invalid_argument(who + ": " + what + " " + detail::quoted_token(t) +
                                  " is not an integer in 1..2147483647");
    return v;
  };
  const std::size_t width = dimension("width");
  const std::size_t height = dimension("height");
  const std::string_view scale_text = token("scale");
  double scale = 0;
  const auto [end, ec] = std::from_chars(scale_text.data(), scale_text.data() + scale_text.size(), scale);
  if (ec != std::errc() || end != scale_text.data() + scale_text.size() || !std::isfinite(scale) || scale == 0)
    throw std::invalid_argument(who + ": scale " + detail::quoted_token(scale_text) +
                                " is not a finite non-zero number (its sign gives the byte order)");
  if (pos >= bytes.size() || !is_space(bytes[pos]))
    throw std::invalid_argument(who + ": no whitespace character after the scale");
  ++pos;  // exactly one whitespace character separates the header from the pixels
  const bool little = scale < 0;

  if (height > bytes.size() / (channels * 4) / width)
    throw std::invalid_argument(who + ": a " + detail::size_text(width, height) +
                                " image is larger than the whole file (" + std::to_string(bytes.size()) + " bytes)");
  const std::size_t expected = width * height * channels * 4;
  if (bytes.size() - pos != expected)
    throw std::invalid_argument(who + ": a " + detail::size_text(width, height) + (channels == 3 ? " PF" : " Pf") +
                                " image needs " + std::to_string(expected) + " bytes of pixels after the header, found " +
                                std::to_string(bytes.size() - pos));
  auto next_float = [&] {
    std::uint32_t u = 0;
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t b = bytes[pos + static_cast<std::size_t>(k)];
      u |= little ? b << (8 * k) : b << (8 * (3 - k));
    }
    pos += 4;
    return std::bit_cast<float>(u);
  };
  image img(width, height);
  for (std::size_t y = height; y-- > 0;)
    for (std::size_t x = 0; x < width; ++x) {
      rgb& p = img.pixels()[y * width + x];
      if (channels == 3) {
        p.r = next_float();
        p.g = next_float();
        p.b = next_float();
      } else {
        p.r = p.g = p.b = next_float();
      }
    }
  return img;
}

// read_pfm(path): reads a PFM file (see parse_pfm for the errors; std::runtime_error with the
// errno text if the file cannot be read).
template <int = 0>
image read_pfm(const std::filesystem::path& path) {
  return parse_pfm(detail::read_whole_file(path, "read_pfm"), path.string());
}

}  // namespace qrm::io

// This header's part of <qrm/io/compiled_io.hpp> (QRM_COMPILED_IO).
#define QRM_DETAIL_PFM_INSTANCES(PREFIX)                                        \
  PREFIX void write_pfm<0>(const std::filesystem::path&, const image&);         \
  PREFIX image parse_pfm<0>(std::span<const std::uint8_t>, const std::string&); \
  PREFIX image read_pfm<0>(const std::filesystem::path&);
#ifdef QRM_COMPILED_IO
namespace qrm::io {
QRM_DETAIL_PFM_INSTANCES(extern template)
}  // namespace qrm::io
#endif
