// The output layer: checksums against published values and bitwise references, PNG structure
// (the pixels themselves are decoded by the independent Python checker, tests/tools/check_png.py,
// from the files this test writes), PFM round trips and header errors, SVG plots and least-squares
// fits, CSV/Markdown tables, atomic file writes, image operations, and the progress bar.
//
// Files for the Python checkers go to $QRM_IO_TEST_DIR (set by ctest), emptied first so that a
// checker never passes on a stale file.
#include <doctest/doctest.h>

#include <qrm/io/atomic_file.hpp>
#include <qrm/io/csv.hpp>
#include <qrm/io/image.hpp>
#include <qrm/io/pfm.hpp>
#include <qrm/io/png.hpp>
#include <qrm/io/progress.hpp>
#include <qrm/io/svg_plot.hpp>
#include <qrm/support/random.hpp>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <csignal>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace qrm::io;

namespace {

// The directory for files the Python checkers read; emptied on first use in this process.
const fs::path& out_dir() {
  static const fs::path dir = [] {
    const char* env = std::getenv("QRM_IO_TEST_DIR");
    fs::path d = env != nullptr && *env != '\0' ? fs::path(env) : fs::path("test_io_out");
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

// Scratch space for this process, removed when the tests end.
struct scratch_root {
  fs::path dir = fs::temp_directory_path() / ("qrm_test_io_" + std::to_string(::getpid()));
  ~scratch_root() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};
scratch_root the_scratch_root;

// A scratch directory for one test case, removed first.
fs::path scratch(const std::string& name) {
  fs::path d = the_scratch_root.dir / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::uint8_t> bytes_of(std::string_view s) { return {s.begin(), s.end()}; }

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> r;
  for (const auto& e : fs::directory_iterator(dir)) r.push_back(e.path().filename().string());
  std::sort(r.begin(), r.end());
  return r;
}

// CRC-32 one bit at a time, straight from the definition (reflected, polynomial 0xEDB88320).
std::uint32_t crc32_bitwise(const std::vector<std::uint8_t>& data) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::uint8_t b : data) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ ((c & 1u) ? 0xEDB88320u : 0u);
  }
  return ~c;
}

// Adler-32 reduced after every byte, straight from RFC 1950.
std::uint32_t adler32_slow(const std::vector<std::uint8_t>& data) {
  std::uint32_t a = 1, b = 0;
  for (std::uint8_t x : data) {
    a = (a + x) % 65521;
    b = (b + a) % 65521;
  }
  return (b << 16) | a;
}

std::vector<std::uint8_t> random_bytes(std::size_t n, std::uint64_t seed) {
  qrm::rng g(seed);
  std::vector<std::uint8_t> v(n);
  for (auto& b : v) b = static_cast<std::uint8_t>(g() >> 56);
  return v;
}

// Writes the expected pixels for check_png.py: "QRMRAW w h c\n" and the bytes (written with
// plain stdio, not through the code under test).
void write_raw(const fs::path& p, const image8& img) {
  std::ofstream out(p, std::ios::binary);
  out << "QRMRAW " << img.width << " " << img.height << " " << img.channels << "\n";
  out.write(reinterpret_cast<const char*>(img.data.data()), static_cast<std::streamsize>(img.data.size()));
  REQUIRE(out.good());
}

std::uint32_t be32(const std::vector<std::uint8_t>& b, std::size_t at) {
  return (std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) | (std::uint32_t{b[at + 2]} << 8) | b[at + 3];
}

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no exception)";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

std::size_t count_of(const std::string& s, const std::string& part) {
  std::size_t n = 0;
  for (std::size_t p = s.find(part); p != std::string::npos; p = s.find(part, p + 1)) ++n;
  return n;
}

// The sRGB transfer function of IEC 61966-2-1, written here independently of image.hpp.
double srgb_reference(double linear) {
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
TEST_CASE("crc32 and adler32 match published check values and bitwise references") {
  CHECK(crc32(bytes_of("123456789")) == 0xCBF43926u);
  CHECK(adler32(bytes_of("Wikipedia")) == 0x11E60398u);
  CHECK(crc32(bytes_of("")) == 0u);
  CHECK(adler32(bytes_of("")) == 1u);
  // Lengths around the 5552-byte deferred reduction of adler32 and far beyond it.
  for (std::size_t n : {1u, 7u, 255u, 5551u, 5552u, 5553u, 11104u, 70001u}) {
    const auto v = random_bytes(n, 1000 + n);
    CHECK(crc32(v) == crc32_bitwise(v));
    CHECK(adler32(v) == adler32_slow(v));
  }
  // All 0xFF bytes: the largest sums, so the deferred modulo would overflow first here.
  const std::vector<std::uint8_t> ones(100000, 0xFF);
  CHECK(adler32(ones) == adler32_slow(ones));
  CHECK(crc32(ones) == crc32_bitwise(ones));
  // Continuation: checksum of a then b == checksum of a + b.
  const auto a = random_bytes(3000, 1), b = random_bytes(9000, 2);
  std::vector<std::uint8_t> ab = a;
  ab.insert(ab.end(), b.begin(), b.end());
  CHECK(crc32(b, crc32(a)) == crc32(ab));
  CHECK(adler32(b, adler32(a)) == adler32(ab));
}

// ---------------------------------------------------------------------------------------------
TEST_CASE("PNG files for the independent checker, and their chunk structure") {
  struct png_case {
    const char* name;
    std::size_t w, h, channels;
  };
  // Sizes: single pixel, one column, one row, odd sizes, grey; raw (filtered) data of exactly
  // 65535 bytes (one full block), 65536 bytes (a second 1-byte block), and 3 blocks.
  const png_case cases[] = {{"rgb_1x1", 1, 1, 3},        {"rgb_1x7", 1, 7, 3},          {"rgb_9x1", 9, 1, 3},
                            {"rgb_37x23", 37, 23, 3},    {"grey_16x5", 16, 5, 1},       {"grey_254x257", 254, 257, 1},
                            {"grey_255x256", 255, 256, 1}, {"rgb_300x160", 300, 160, 3}};
  std::uint64_t seed = 7;
  image8 rgb_37x23;
  for (const auto& c : cases) {
    CAPTURE(c.name);
    image8 img{c.w, c.h, c.channels, random_bytes(c.w * c.h * c.channels, ++seed)};
    if (std::string(c.name) == "rgb_37x23") rgb_37x23 = img;
    write_png(out_dir() / (std::string(c.name) + ".png"), img);
    write_raw(out_dir() / (std::string(c.name) + ".raw"), img);

    // Structure, read back with the test's own bitwise CRC.
    const std::string file = slurp(out_dir() / (std::string(c.name) + ".png"));
    const std::vector<std::uint8_t> png(file.begin(), file.end());
    REQUIRE(png.size() > 8 + 25 + 12 + 12);
    CHECK(std::memcmp(png.data(), "\x89PNG\r\n\x1a\n", 8) == 0);
    std::size_t pos = 8;
    std::vector<std::string> types;
    std::vector<std::uint8_t> idat;
    while (pos < png.size()) {
      const std::uint32_t len = be32(png, pos);
      REQUIRE(pos + 12 + len <= png.size());
      types.emplace_back(reinterpret_cast<const char*>(&png[pos + 4]), 4);
      const std::vector<std::uint8_t> typed(png.begin() + static_cast<std::ptrdiff_t>(pos + 4),
                                            png.begin() + static_cast<std::ptrdiff_t>(pos + 8 + len));
      CHECK(be32(png, pos + 8 + len) == crc32_bitwise(typed));
      if (types.back() == "IHDR") {
        CHECK(len == 13);
        CHECK(be32(png, pos + 8) == c.w);
        CHECK(be32(png, pos + 12) == c.h);
        CHECK(png[pos + 16] == 8);
        CHECK(png[pos + 17] == (c.channels == 3 ? 2 : 0));
      }
      if (types.back() == "IDAT") idat.insert(idat.end(), typed.begin() + 4, typed.end());
      pos += 12 + len;
    }
    CHECK(types == std::vector<std::string>{"IHDR", "IDAT", "IEND"});
    // The stored blocks: sizes from the definition (rows of 1 + width * channels bytes).
    const std::size_t raw = c.h * (1 + c.w * c.channels);
    const std::size_t blocks = (raw + 65534) / 65535;
    CHECK(idat.size() == 2 + 5 * blocks + raw + 4);
    CHECK(idat[0] == 0x78);
    CHECK(idat[1] == 0x01);
  }

  // For checker tests that must fail: an all-equal image, a wrong expected dump (one byte
  // changed), and a file with one pixel byte flipped after its CRC was computed.
  image8 blank{5, 4, 3, std::vector<std::uint8_t>(60, 77)};
  write_png(out_dir() / "blank.png", blank);
  REQUIRE(rgb_37x23.data.size() == 37 * 23 * 3);
  rgb_37x23.data[100] ^= 1;
  write_raw(out_dir() / "rgb_37x23_wrong.raw", rgb_37x23);
  std::string corrupt = slurp(out_dir() / "rgb_37x23.png");
  corrupt[corrupt.size() - 12 - 4 - 10] ^= 0x10;  // inside IDAT's pixel data, before the Adler-32
  write_file_atomically(out_dir() / "corrupt.png", corrupt);

  // A tone-mapped gradient through write_png(image): the checker's "non-blank" mode.
  image grad(64, 16);
  for (std::size_t y = 0; y < 16; ++y)
    for (std::size_t x = 0; x < 64; ++x) grad.at(x, y) = {x / 63.0f, y / 15.0f, 0.25f};
  write_png(out_dir() / "gradient.png", grad);
  write_raw(out_dir() / "gradient.raw", to_srgb8(grad));
}

TEST_CASE("encode_png rejects bad images by name") {
  CHECK(contains(error_of([] { encode_png(image8{0, 3, 3, {}}); }), "0x3"));
  CHECK(contains(error_of([] { encode_png(image8{2, 2, 2, std::vector<std::uint8_t>(8)}); }), "2 channels"));
  CHECK(contains(error_of([] { encode_png(image8{2, 2, 3, std::vector<std::uint8_t>(11)}); }), "11 bytes"));
  CHECK(contains(error_of([] { write_png(out_dir() / "never.png", image{}); }), "empty"));
  CHECK_FALSE(fs::exists(out_dir() / "never.png"));
}

TEST_CASE("write_png rejects NaN and infinite pixels, naming the pixel, and writes nothing") {
  const fs::path dir = scratch("nan");
  image img(4, 3, {0.5f, 0.5f, 0.5f});
  img.at(2, 1).g = std::numeric_limits<float>::quiet_NaN();
  const std::string e = error_of([&] { write_png(dir / "nan.png", img); });
  CHECK(contains(e, "pixel (2, 1)"));
  CHECK(contains(e, "channel G"));
  CHECK(contains(e, "nan"));
  img.at(2, 1).g = 0;
  img.at(3, 2).b = -std::numeric_limits<float>::infinity();
  const std::string e2 = error_of([&] { write_png(dir / "nan.png", img); });
  CHECK(contains(e2, "pixel (3, 2) channel B is -inf"));
  CHECK(names_in(dir).empty());
  CHECK(contains(error_of([&] { to_srgb8(image(1, 1), {0.0f}); }), "exposure 0"));
  CHECK(contains(error_of([] { to_8bit(std::numeric_limits<float>::quiet_NaN()); }), "to_8bit: value nan"));
  CHECK(contains(error_of([] { to_8bit(0.5f, {std::numeric_limits<float>::quiet_NaN()}); }), "exposure nan"));
  CHECK(contains(error_of([&] { to_srgb8(image(1, 1), {std::numeric_limits<float>::infinity()}); }), "exposure inf"));
}

// ---------------------------------------------------------------------------------------------
TEST_CASE("tone mapping: sRGB and gamma 2.2 against their definitions, monotonic, clamped") {
  // Published pair: 8-bit sRGB 128 is linear 0.21586 (128/255 = 0.50196 through the inverse curve).
  CHECK(to_8bit(0.21586f) == 128);
  CHECK(to_8bit(0.0f) == 0);
  CHECK(to_8bit(1.0f) == 255);
  CHECK(to_8bit(-3.0f) == 0);    // negative estimates clamp to black
  CHECK(to_8bit(42.0f) == 255);  // over-exposed values clamp to white
  CHECK(to_8bit(0.25f, {4.0f}) == 255);
  CHECK(to_8bit(0.5f, {1.0f, transfer_curve::gamma22}) == 186);  // 0.5^(1/2.2) * 255 = 186.08
  for (int i = 0; i <= 2000; ++i) {
    const float v = static_cast<float>(i) / 2000.0f;
    CAPTURE(v);
    CHECK(to_8bit(v) == static_cast<int>(std::floor(srgb_reference(v) * 255 + 0.5)));
    CHECK(to_8bit(v, {1.0f, transfer_curve::gamma22}) == static_cast<int>(std::floor(std::pow(v, 1 / 2.2) * 255 + 0.5)));
  }
  // Monotonic over a range that crosses both clamps, for both curves and two exposures.
  for (auto curve : {transfer_curve::srgb, transfer_curve::gamma22})
    for (float exposure : {1.0f, 3.5f}) {
      int prev = -1;
      double prev_display = -1;
      for (int i = -500; i <= 3000; ++i) {
        const float v = static_cast<float>(i) / 2000.0f;
        const int q = to_8bit(v, {exposure, curve});
        CHECK(q >= prev);
        prev = q;
        const double d = encode_display(std::clamp(v * static_cast<double>(exposure), 0.0, 1.0), curve);
        CHECK(d >= prev_display);
        prev_display = d;
      }
    }
  // decode_display inverts encode_display (1e-12: a few rounding steps of pow on values <= 1).
  for (auto curve : {transfer_curve::srgb, transfer_curve::gamma22})
    for (double v : {0.0, 0.001, 0.0031308, 0.01, 0.2, 0.5, 0.9, 1.0})
      CHECK(decode_display(encode_display(v, curve), curve) == doctest::Approx(v).epsilon(1e-12));
}

// ---------------------------------------------------------------------------------------------
TEST_CASE("image::at names the coordinates and the size") {
  image img(4, 3);
  CHECK(contains(error_of([&] { (void)img.at(4, 0); }), "(4, 0) is outside the 4x3 image"));
  CHECK(contains(error_of([&] { (void)img.at(0, 3); }), "(0, 3)"));
  CHECK(contains(error_of([] { image(0, 5); }), "0x5"));
  img.at(3, 2) = {1, 2, 3};
  CHECK(img.pixels()[2 * 4 + 3] == rgb{1, 2, 3});
}

TEST_CASE("bilinear upsampling: hand-computed examples") {
  // 1-D: values 1 and 6 at cell centres, 2 -> 10 pixels (factor 5). Output pixel i samples
  // u = (i + 0.5) / 5 - 0.5: pixels 0-2 are at or left of centre 0 (held at 1), 7-9 at or right
  // of centre 1 (held at 6), and 3..6 step by 1/5 of the way: 2, 3, 4, 5.
  image row(2, 1);
  row.at(0, 0) = {1, 10, -1};
  row.at(1, 0) = {6, 0, 4};
  const image up = upsample_bilinear(row, 10, 1);
  const float expect_r[10] = {1, 1, 1, 2, 3, 4, 5, 6, 6, 6};
  const float expect_g[10] = {10, 10, 10, 8, 6, 4, 2, 0, 0, 0};
  for (std::size_t i = 0; i < 10; ++i) {
    CAPTURE(i);
    // 1e-6: the weights (k/5) are not exact in binary; one float rounding of values <= 10.
    CHECK(up.at(i, 0).r == doctest::Approx(expect_r[i]).epsilon(1e-6));
    CHECK(up.at(i, 0).g == doctest::Approx(expect_g[i]).epsilon(1e-6));
  }
  // 2-D: 2x2 cells r = 4 x + 8 y, 2 -> 4 pixels per side: sample coordinates 0 (clamped), 1/4,
  // 3/4, 1 (clamped) in each direction, so r = 4 u + 8 v on that grid (all exact in binary).
  image sq(2, 2);
  sq.at(0, 0).r = 0;
  sq.at(1, 0).r = 4;
  sq.at(0, 1).r = 8;
  sq.at(1, 1).r = 12;
  const image up2 = upsample_bilinear(sq, 2);
  const float expect[4][4] = {{0, 1, 3, 4}, {2, 3, 5, 6}, {6, 7, 9, 10}, {8, 9, 11, 12}};
  for (std::size_t y = 0; y < 4; ++y)
    for (std::size_t x = 0; x < 4; ++x) {
      CAPTURE(x);
      CAPTURE(y);
      CHECK(up2.at(x, y).r == expect[y][x]);
    }
}

TEST_CASE("bilinear upsampling: exact at cell centres, linear in between (8x8 light map, factor 5)") {
  qrm::rng g(99);
  image map(8, 8);
  for (auto& p : map.pixels())
    p = {static_cast<float>(g.uniform()), static_cast<float>(g.uniform()), static_cast<float>(g.uniform())};
  const image up = upsample_bilinear(map, 40, 40);
  for (std::size_t cy = 0; cy < 8; ++cy)
    for (std::size_t cx = 0; cx < 8; ++cx) CHECK(up.at(5 * cx + 2, 5 * cy + 2) == map.at(cx, cy));  // bit-exact
  // Every pixel against bilinear interpolation written from the definition, in double.
  double worst = 0;
  for (std::size_t j = 0; j < 40; ++j)
    for (std::size_t i = 0; i < 40; ++i) {
      const double u = std::clamp((i + 0.5) / 5.0 - 0.5, 0.0, 7.0), v = std::clamp((j + 0.5) / 5.0 - 0.5, 0.0, 7.0);
      const auto x0 = static_cast<std::size_t>(std::min(std::floor(u), 6.0)), y0 = static_cast<std::size_t>(std::min(std::floor(v), 6.0));
      const double fx = u - static_cast<double>(x0), fy = v - static_cast<double>(y0);
      auto r = [&](std::size_t x, std::size_t y) { return static_cast<double>(map.at(x, y).r); };
      const double want = (1 - fy) * ((1 - fx) * r(x0, y0) + fx * r(x0 + 1, y0)) + fy * ((1 - fx) * r(x0, y0 + 1) + fx * r(x0 + 1, y0 + 1));
      worst = std::max(worst, std::fabs(want - up.at(i, j).r));
    }
  CHECK(worst < 1e-6);  // values in [0, 1) stored as float: rounding below 6e-8, plus weight rounding
  CHECK(contains(error_of([&] { upsample_bilinear(map, 0, 4); }), "0x4"));
  CHECK(contains(error_of([] { upsample_bilinear(image{}, 4, 4); }), "empty"));
}

TEST_CASE("nearest upsampling: blocks, and the cell each pixel centre falls in") {
  image src(3, 1);
  for (std::size_t x = 0; x < 3; ++x) src.at(x, 0).r = static_cast<float>(x);
  const image blocks = upsample_nearest(src, 4);
  CHECK(blocks.width() == 12);
  CHECK(blocks.height() == 4);
  for (std::size_t y = 0; y < 4; ++y)
    for (std::size_t x = 0; x < 12; ++x) CHECK(blocks.at(x, y).r == static_cast<float>(x / 4));
  // 3 -> 4 pixels: centres at 3/8, 9/8, 15/8, 21/8 source cells -> cells 0, 1, 1, 2.
  const image odd = upsample_nearest(src, 4, 1);
  CHECK(odd.at(0, 0).r == 0);
  CHECK(odd.at(1, 0).r == 1);
  CHECK(odd.at(2, 0).r == 1);
  CHECK(odd.at(3, 0).r == 2);
}

TEST_CASE("difference, false colour, side by side, statistics") {
  image a(3, 2, {1, 2, 3}), b(3, 2, {1.5f, 2, 1});
  const image d = absolute_difference(a, b);
  for (const rgb& p : d.pixels()) CHECK(p == rgb{0.5f, 0, 2});
  CHECK(contains(error_of([&] { absolute_difference(a, image(2, 3)); }), "3x2 vs 2x3"));

  // rmse: per channel differences 0.5, 0, 2 -> sqrt((0.25 + 0 + 4) / 3).
  // 1e-15: both sides are the same quotient rounded once, then sqrt (half an ulp each).
  CHECK(rmse(a, b) == doctest::Approx(std::sqrt(4.25 / 3)).epsilon(1e-15));
  CHECK(rmse(a, a) == 0);
  const image_stats s = stats(a);
  CHECK(s.min == 1);
  CHECK(s.max == 3);
  CHECK(s.mean == 2);
  image bad = a;
  bad.at(1, 1).r = std::numeric_limits<float>::quiet_NaN();
  CHECK(contains(error_of([&] { stats(bad); }), "pixel (1, 1) channel R is nan"));

  // The ramp's documented stops, shown through to_srgb8: black and pale yellow (1, 1, 0.75).
  auto shown = [](rgb p) {
    image one(1, 1, p);
    return to_srgb8(one).data;
  };
  CHECK(shown(error_ramp(0)) == std::vector<std::uint8_t>{0, 0, 0});
  CHECK(shown(error_ramp(1)) == std::vector<std::uint8_t>{255, 255, 191});  // 0.75 * 255 = 191.25
  CHECK(shown(error_ramp(0.75f)) == std::vector<std::uint8_t>{255, 153, 0});  // orange (1, 0.6, 0)
  CHECK(shown(error_ramp(7)) == shown(error_ramp(1)));                          // clamped above
  // Display luminance (Rec. 709 weights on the display values) rises strictly along the ramp.
  double prev = -1;
  for (int i = 0; i <= 400; ++i) {
    const rgb c = error_ramp(static_cast<float>(i) / 400.0f);
    const double lum = 0.2126 * srgb_reference(c.r) + 0.7152 * srgb_reference(c.g) + 0.0722 * srgb_reference(c.b);
    CHECK(lum > prev);
    prev = lum;
  }
  image err(2, 1);
  err.at(0, 0) = {0, 0, 0};
  err.at(1, 0) = {0.25f, 0.5f, 0.75f};  // mean 0.5 (exact in binary)
  const image fc = false_colour(err, 1.0f);
  CHECK(fc.at(0, 0) == error_ramp(0));
  CHECK(fc.at(1, 0) == error_ramp(0.5f));
  CHECK(false_colour(err).at(1, 0) == error_ramp(1));
  CHECK(contains(error_of([&] { false_colour(err, -1); }), "max_value -1"));

  // Panels: 2x3 and 3x1 with a 2-pixel gap -> 7x3; the short panel starts at row (3 - 1) / 2 = 1.
  image p1(2, 3, {1, 0, 0}), p2(3, 1, {0, 1, 0});
  const image both = side_by_side(p1, p2, 2, {0, 0, 1});
  CHECK(both.width() == 7);
  CHECK(both.height() == 3);
  for (std::size_t y = 0; y < 3; ++y) {
    CAPTURE(y);
    CHECK(both.at(1, y) == rgb{1, 0, 0});  // first panel, full height
    CHECK(both.at(2, y) == rgb{0, 0, 1});  // gap
    CHECK(both.at(3, y) == rgb{0, 0, 1});
    for (std::size_t x = 4; x < 7; ++x) CHECK(both.at(x, y) == (y == 1 ? rgb{0, 1, 0} : rgb{0, 0, 1}));
  }
  CHECK(contains(error_of([] { side_by_side(std::span<const image>{}); }), "no panels"));
}

// ---------------------------------------------------------------------------------------------
TEST_CASE("PFM: bit-exact round trip, byte layout, both byte orders, grey") {
  const fs::path dir = scratch("pfm");
  qrm::rng g(5);
  for (auto [w, h] : {std::pair<std::size_t, std::size_t>{1, 1}, {7, 3}, {2, 9}}) {
    image img(w, h);
    for (auto& p : img.pixels())  // arbitrary bit patterns: negative, denormal, huge, NaN payloads
      p = {std::bit_cast<float>(static_cast<std::uint32_t>(g())), std::bit_cast<float>(static_cast<std::uint32_t>(g())),
           static_cast<float>(g.uniform())};
    img.pixels()[0].r = -0.0f;
    img.pixels()[0].g = std::numeric_limits<float>::infinity();
    write_pfm(dir / "x.pfm", img);
    const image back = read_pfm(dir / "x.pfm");
    REQUIRE(back.width() == w);
    REQUIRE(back.height() == h);
    for (std::size_t k = 0; k < img.pixels().size(); ++k)
      for (float rgb::*c : {&rgb::r, &rgb::g, &rgb::b})
        CHECK(std::bit_cast<std::uint32_t>(back.pixels()[k].*c) == std::bit_cast<std::uint32_t>(img.pixels()[k].*c));
  }
  // A 1x2 image: the file holds the bottom row first, little-endian (1.0f = 00 00 80 3F).
  image two(1, 2);
  two.at(0, 0) = {1, 2, 0.5f};
  two.at(0, 1) = {-2, 0, 1};
  write_pfm(dir / "two.pfm", two);
  const std::string expected = std::string("PF\n1 2\n-1.0\n") +
                               std::string("\x00\x00\x00\xC0\x00\x00\x00\x00\x00\x00\x80\x3F", 12) +  // -2, 0, 1
                               std::string("\x00\x00\x80\x3F\x00\x00\x00\x40\x00\x00\x00\x3F", 12);   // 1, 2, 0.5
  CHECK(slurp(dir / "two.pfm") == expected);
  // The same image big-endian (positive scale) and with other whitespace.
  const std::string big = std::string("PF 1\t2\r\n1.0\n") + std::string("\xC0\x00\x00\x00\x00\x00\x00\x00\x3F\x80\x00\x00", 12) +
                          std::string("\x3F\x80\x00\x00\x40\x00\x00\x00\x3F\x00\x00\x00", 12);
  CHECK(parse_pfm(bytes_of(big)) == two);
  // Grey: one float per pixel, copied to R, G and B.
  const image grey = parse_pfm(bytes_of(std::string("Pf\n2 1\n-1\n") + std::string("\x00\x00\x80\x3F\x00\x00\x00\x40", 8)));
  CHECK(grey.at(0, 0) == rgb{1, 1, 1});
  CHECK(grey.at(1, 0) == rgb{2, 2, 2});
}

TEST_CASE("PFM: bad headers and sizes are rejected with clear messages") {
  auto err = [](const std::string& s) { return error_of([&] { parse_pfm(bytes_of(s), "f.pfm"); }); };
  const std::string px(12, '\0');
  CHECK(contains(err("P6\n1 1\n255\n" + px), "not a PFM file (magic 'P6'"));
  CHECK(contains(err("PF\nabc 1\n-1.0\n" + px), "width 'abc' is not an integer"));
  CHECK(contains(err("PF\n0 1\n-1.0\n" + px), "width '0'"));
  CHECK(contains(err("PF\n1 -1\n-1.0\n" + px), "height '-1'"));
  CHECK(contains(err("PF\n1 1\n0\n" + px), "scale '0' is not a finite non-zero number"));
  CHECK(contains(err("PF\n1 1\nfast\n" + px), "scale 'fast'"));
  CHECK(contains(err("PF\n1 1\n"), "ends before the scale"));
  CHECK(contains(err("PF\n1 1\n-1.0"), "no whitespace character after the scale"));
  CHECK(contains(err("PF\n1 1\n-1.0\n" + px.substr(4)), "needs 12 bytes of pixels after the header, found 8"));
  CHECK(contains(err("PF\n1 1\n-1.0\n" + px + "x"), "found 13"));
  CHECK(contains(err("PF\n100000 100000\n-1.0\n" + px), "larger than the whole file"));
  CHECK(contains(err(""), "ends before the magic number"));
  CHECK_NOTHROW(parse_pfm(bytes_of("PF\n1 1\n-1.0\n" + px)));  // the same header, correct
  CHECK(contains(error_of([] { read_pfm("/nonexistent/dir/x.pfm"); }), "'/nonexistent/dir/x.pfm': No such file"));
}

// ---------------------------------------------------------------------------------------------
TEST_CASE("least-squares fits: exact power laws, a hand example, refusals") {
  std::vector<double> x, y;
  for (double v = 1; v <= 1e6; v *= 3.7) {
    x.push_back(v);
    y.push_back(3 * std::pow(v, -0.5));
  }
  const line_fit f = fit_log_log(x, y);
  // 1e-12: log10 of the inputs is correct to ~1e-16 relative; the sums lose at most a few digits.
  CHECK(std::fabs(f.slope - (-0.5)) < 1e-12);
  CHECK(std::fabs(f.intercept - std::log10(3.0)) < 1e-12);
  CHECK(std::fabs(f.r_squared - 1) < 1e-12);
  CHECK(f.points == x.size());
  // Points (0, 1), (1, 3), (2, 2): slope 1/2, intercept 3/2, residuals -1/2, 1, -1/2 so
  // SS_res = 3/2, SS_tot = 2, r^2 = 1/4 (all exact in binary).
  const std::vector<double> hx{0, 1, 2}, hy{1, 3, 2};
  const line_fit h = fit_line(hx, hy);
  CHECK(h.slope == 0.5);
  CHECK(h.intercept == 1.5);
  CHECK(h.r_squared == 0.25);
  CHECK(contains(error_of([] { fit_line(std::vector<double>{1}, std::vector<double>{2}); }), "at least 2 points, got 1"));
  CHECK(contains(error_of([] { fit_log_log(std::vector<double>{}, std::vector<double>{}); }), "got 0"));
  CHECK(contains(error_of([] { fit_line(std::vector<double>{2, 2}, std::vector<double>{1, 3}); }), "all x are equal (2)"));
  CHECK(contains(error_of([] { fit_log_log(std::vector<double>{1, 2, 3}, std::vector<double>{1, 0, 3}); }),
                 "point 1 (2, 0) is not positive"));
  CHECK(contains(error_of([] { fit_line(std::vector<double>{1, 2}, std::vector<double>{1}); }), "2 x values but 1 y"));
}

TEST_CASE("SVG plots: files for the XML checker, log-axis refusals, escaping, ticks") {
  plot conv;
  conv.title = "Error < 1 & \"quoted\" 'names' \xC3\xBC";  // u-umlaut in UTF-8
  conv.x_label = "estimates (paths / circuit runs)";
  conv.y_label = "RMSE";
  conv.x_scale = conv.y_scale = axis_scale::log10;
  plot_series mc{"Monte Carlo", {}, {}, "", marker::circle, true, true};
  plot_series qa{"quantum <QAE>", {}, {}, "#c8412b", marker::square, true, true};
  for (double n = 10; n <= 1e5; n *= 10) {
    mc.x.push_back(n);
    mc.y.push_back(0.8 * std::pow(n, -0.471));
    qa.x.push_back(n);
    qa.y.push_back(5 * std::pow(n, -1.407));
  }
  conv.series = {mc, qa};
  const std::string svg = render_svg(conv);
  CHECK(contains(svg, "Error &lt; 1 &amp; &quot;quoted&quot; &apos;names&apos; \xC3\xBC"));
  CHECK_FALSE(contains(svg, "Error < 1"));
  CHECK(contains(svg, "Monte Carlo (fit slope -0.471)"));
  CHECK(contains(svg, "quantum &lt;QAE&gt; (fit slope -1.407)"));
  CHECK(count_of(svg, "stroke-dasharray") == 2);  // one dashed fitted line per fitted series
  CHECK(render_svg(conv) == svg);                 // deterministic
  write_svg(out_dir() / "convergence.svg", conv);

  // Linear axes with negative data: x in [-3, 7.3] -> step 2, ticks -4 .. 8.
  plot lin;
  lin.title = "linear";
  lin.series = {{"s", {-3, 0, 7.3}, {-1, 0.5, 2}, "teal", marker::triangle, false, false}};
  const std::string lsvg = render_svg(lin);
  for (const char* t : {">-4</text>", ">-2</text>", ">0</text>", ">2</text>", ">4</text>", ">6</text>", ">8</text>"})
    CHECK(contains(lsvg, t));
  CHECK_FALSE(contains(lsvg, ">10</text>"));
  // The automatic legend avoids the top-right point: it goes to the empty top-left corner.
  const std::size_t legend_at = lsvg.find("<g class=\"legend\">\n<rect x=\"");
  REQUIRE(legend_at != std::string::npos);
  CHECK(std::stod(lsvg.substr(legend_at + 28)) < 100);
  write_svg(out_dir() / "linear.svg", lin);

  // Refusals, each naming the series and the point.
  plot bad = conv;
  bad.series[1].y[2] = 0;
  CHECK(contains(error_of([&] { render_svg(bad); }),
                 "series 'quantum <QAE>' point 2 has y = 0; a log10 axis can only show positive values"));
  bad = conv;
  bad.series[0].x[0] = -1;
  CHECK(contains(error_of([&] { render_svg(bad); }), "series 'Monte Carlo' point 0 has x = -1"));
  bad = lin;
  bad.series[0].y[1] = std::numeric_limits<double>::quiet_NaN();
  CHECK(contains(error_of([&] { render_svg(bad); }), "point 1 has y = nan, which is not finite"));
  bad = lin;
  bad.series[0].y.pop_back();
  CHECK(contains(error_of([&] { render_svg(bad); }), "has 3 x values but 2 y values"));
  bad = lin;
  bad.series[0].colour = "red\" onload=\"x";
  CHECK(contains(error_of([&] { render_svg(bad); }), "is not #rgb, #rrggbb or a colour name"));
  bad = lin;
  bad.series[0].fit = true;
  bad.series[0].x = {1, 1, 1};
  CHECK(contains(error_of([&] { render_svg(bad); }), "series 's' cannot be fitted: fit_line: all x are equal"));
  bad = lin;
  bad.title = "bell\x07";
  CHECK(contains(error_of([&] { render_svg(bad); }), "control character 7"));
  bad.title = "cut \xC3";
  CHECK(contains(error_of([&] { render_svg(bad); }), "invalid UTF-8 at byte 4"));
}

// ---------------------------------------------------------------------------------------------
TEST_CASE("CSV quoting, round-trip numbers, Markdown tables") {
  // RFC 4180 quoting, hand-written.
  CHECK(csv_quote("plain") == "plain");
  CHECK(csv_quote("") == "");
  CHECK(csv_quote("a,b") == "\"a,b\"");
  CHECK(csv_quote("say \"hi\"") == "\"say \"\"hi\"\"\"");
  CHECK(csv_quote("two\nlines") == "\"two\nlines\"");
  CHECK(csv_quote(" padded") == "\" padded\"");
  // Numbers read back to the same double, and are no longer than printf's %.{p}g with the
  // smallest precision p that reads back (to_chars may write an integer-valued double in full,
  // 37470267394548808 rather than 3.747026739454881e+16: fewer characters, more digits).
  qrm::rng g(11);
  for (int i = 0; i < 2000; ++i) {
    double v = std::bit_cast<double>(g());
    if (std::isnan(v)) continue;
    if (i % 2) v = g.uniform() * std::pow(10.0, static_cast<int>(g.below(40)) - 20);
    const std::string text = csv_number(v);
    CHECK(std::bit_cast<std::uint64_t>(std::strtod(text.c_str(), nullptr)) == std::bit_cast<std::uint64_t>(v));
    char ref[64];
    for (int p = 1; p <= 17; ++p) {
      std::snprintf(ref, sizeof ref, "%.*g", p, v);
      if (std::strtod(ref, nullptr) == v) break;
    }
    CHECK(text.size() <= std::strlen(ref));
  }
  CHECK(csv_number(0.1) == "0.1");
  CHECK(csv_number(0.2 + 0.1) == "0.30000000000000004");
  CHECK(csv_number(std::numeric_limits<double>::infinity()) == "inf");

  table t({"method", "n", "error, rms"});
  t.add_row({"Monte Carlo", 1000, 0.1});
  t.add_row({"a|b \"q\"", std::uint64_t{18446744073709551615u}, 2.5});
  CHECK(to_csv(t) ==
        "method,n,\"error, rms\"\n"
        "Monte Carlo,1000,0.1\n"
        "\"a|b \"\"q\"\"\",18446744073709551615,2.5\n");
  CHECK(to_markdown(t, 3) ==
        "| method | n | error, rms |\n"
        "| --- | ---: | ---: |\n"
        "| Monte Carlo | 1000 | 0.1 |\n"
        "| a\\|b \"q\" | 18446744073709551615 | 2.5 |\n");
  CHECK(contains(error_of([&] { t.add_row({"x", 1}); }), "row 2 has 2 cells but the header has 3 columns"));
  CHECK(contains(error_of([&] { to_markdown(t, 0); }), "significant_digits 0"));
  table nl({"a"});
  nl.add_row({"x\ny"});
  CHECK(contains(error_of([&] { to_markdown(nl); }), "contains a line break"));
  const fs::path dir = scratch("csv");
  write_csv(dir / "t.csv", t);
  CHECK(slurp(dir / "t.csv") == to_csv(t));
}

// ---------------------------------------------------------------------------------------------
TEST_CASE("atomic writes: missing directories are created, failures leave nothing behind") {
  const fs::path dir = scratch("atomic");
  write_file_atomically(dir / "a" / "b" / "c" / "f.txt", "hello");
  CHECK(slurp(dir / "a" / "b" / "c" / "f.txt") == "hello");
  CHECK(names_in(dir / "a" / "b" / "c") == std::vector<std::string>{"f.txt"});

  // A path component is a file: clear error naming the directory, nothing created.
  write_file_atomically(dir / "blocker", "I am a file");
  const std::string e1 = error_of([&] { write_file_atomically(dir / "blocker" / "x" / "y.txt", "z"); });
  CHECK(contains(e1, "cannot create directory '" + (dir / "blocker" / "x").string() + "'"));
  CHECK(contains(e1, "Not a directory"));
  CHECK(slurp(dir / "blocker") == "I am a file");

  // The target is a directory: the rename fails; the error names it and no temp file remains.
  const fs::path sub = scratch("atomic_dir");
  fs::create_directory(sub / "target");
  const std::string e2 = error_of([&] { write_file_atomically(sub / "target", std::string(100000, 'x')); });
  CHECK(contains(e2, "'" + (sub / "target").string() + "'"));
  CHECK(contains(e2, "Is a directory"));
  CHECK(names_in(sub) == std::vector<std::string>{"target"});
  CHECK(fs::is_empty(sub / "target"));

  // The writer throws after writing part of the content: the old file stays, no temp file.
  const fs::path keep = scratch("atomic_throw");
  write_file_atomically(keep / "result.txt", "old content");
  bool wrote_part = false;
  CHECK_THROWS_WITH_AS(write_file_atomically(keep / "result.txt",
                                             [&](file_sink& out) {
                                               out.write(std::string(50000, 'n'));
                                               wrote_part = out.bytes_written() == 50000;
                                               throw std::logic_error("renderer failed halfway");
                                             }),
                       "renderer failed halfway", std::logic_error);
  CHECK(wrote_part);
  CHECK(slurp(keep / "result.txt") == "old content");
  CHECK(names_in(keep) == std::vector<std::string>{"result.txt"});

  // Success replaces the content and leaves only the target.
  write_file_atomically(keep / "result.txt", "new content");
  CHECK(slurp(keep / "result.txt") == "new content");
  CHECK(names_in(keep) == std::vector<std::string>{"result.txt"});

  CHECK(contains(error_of([] { write_file_atomically("", "x"); }), "empty"));
  CHECK(contains(error_of([&] { write_file_atomically(keep / "", "x"); }), "does not name a file"));
}

// Runs a child that starts writing `target` and sends itself `sig` halfway; returns the child's
// wait status. With `handlers`, the child first calls remove_temporary_files_on_signals().
static int interrupted_write(const fs::path& target, int sig, bool handlers) {
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    if (handlers)
      remove_temporary_files_on_signals();
    else
      std::signal(sig, SIG_DFL);  // not doctest's crash reporter: the default action, as in a plain program
    write_file_atomically(target, [&](file_sink& out) {
      out.write(std::string(1 << 20, 'p'));
      bool temp_exists = false;  // the signal must find a temporary file to remove
      for (const auto& e : fs::directory_iterator(target.parent_path()))
        temp_exists = temp_exists || e.path().filename().string().ends_with(".tmp");
      if (!temp_exists) ::_exit(3);
      ::raise(sig);
      out.write(std::string(1 << 20, 'q'));
    });
    ::_exit(4);  // the signal did not stop the write
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

TEST_CASE("atomic writes: SIGTERM, SIGINT or SIGHUP mid-write removes the temporary file, exit 128 + signal") {
  for (int sig : {SIGTERM, SIGINT, SIGHUP}) {
    CAPTURE(sig);
    const fs::path dir = scratch("atomic_signal_" + std::to_string(sig));
    write_file_atomically(dir / "image.pfm", "old content");
    const int status = interrupted_write(dir / "image.pfm", sig, true);
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 128 + sig);
    CHECK(names_in(dir) == std::vector<std::string>{"image.pfm"});
    CHECK(slurp(dir / "image.pfm") == "old content");
  }
  // Without the handlers the signal kills the writer and its temporary file stays: what the
  // handlers are for (and proof that the check above can fail).
  const fs::path dir = scratch("atomic_signal_default");
  const int status = interrupted_write(dir / "image.pfm", SIGTERM, false);
  REQUIRE(WIFSIGNALED(status));
  CHECK(WTERMSIG(status) == SIGTERM);
  const auto left = names_in(dir);
  REQUIRE(left.size() == 1);
  CHECK(left[0].ends_with(".tmp"));
}

TEST_CASE("atomic writes: a concurrent reader sees the old or the new content, never a mixture") {
  const fs::path dir = scratch("atomic_race");
  const fs::path target = dir / "shared.bin";
  constexpr std::size_t size = 300000;  // several stdio buffers, so a torn write would show
  write_file_atomically(target, std::string(size, 'a'));
  std::atomic<bool> stop{false};
  std::atomic<int> reads{0}, torn{0};
  std::thread reader([&] {
    while (!stop.load()) {
      const std::string s = slurp(target);
      const bool whole = s.size() == size && std::all_of(s.begin(), s.end(), [&](char c) { return c == s[0]; });
      if (!whole) ++torn;
      ++reads;
    }
  });
  std::vector<std::thread> writers;
  for (int w = 0; w < 3; ++w)
    writers.emplace_back([&, w] {
      for (int k = 0; k < 15; ++k) write_file_atomically(target, std::string(size, static_cast<char>('b' + w)));
    });
  for (auto& t : writers) t.join();
  stop = true;
  reader.join();
  CHECK(torn.load() == 0);
  CHECK(reads.load() > 0);
  CHECK(names_in(dir) == std::vector<std::string>{"shared.bin"});  // unique temp names, all renamed
}

// ---------------------------------------------------------------------------------------------
namespace {
std::string read_stream(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string s;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) s.append(buf, n);
  return s;
}
}  // namespace

TEST_CASE("progress: thread-safe count, rate-limited redraws, one line ended by finish()") {
  std::FILE* f = std::tmpfile();
  REQUIRE(f != nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  std::uint64_t redraws = 0;
  {
    progress bar("render", 80000, {false, progress_style::terminal, f});
    std::vector<std::thread> workers;
    for (int w = 0; w < 4; ++w)
      workers.emplace_back([&] {
        for (int k = 0; k < 20000; ++k) bar.advance();
      });
    for (auto& t : workers) t.join();
    CHECK(bar.done() == 80000);
    bar.message("a log line");
    bar.finish();
    bar.finish();  // idempotent
    redraws = bar.redraws();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string out = read_stream(f);
  std::fclose(f);
  CAPTURE(out);
  // Rate limit: one draw per 100 ms at most, plus the first draw, the redraw after message()
  // and the final one (an upper bound that only grows with the time taken, so it holds on any machine).
  CHECK(redraws <= static_cast<std::uint64_t>(seconds / 0.1) + 3);
  CHECK(count_of(out, "\r") >= redraws);
  CHECK(contains(out, "\ra log line\n"));
  CHECK(out.back() == '\n');
  CHECK(count_of(out, "\n") == 2);  // the message and the end of the bar
  const std::string last = out.substr(out.rfind('\r'));
  CHECK(contains(last, "render [##############################] 100.0%  80000/80000  elapsed"));

  // quiet: nothing at all; plain style with a long interval: a short job prints nothing.
  for (progress_options opt : {progress_options{true, progress_style::terminal}, progress_options{false, progress_style::plain},
                               progress_options{false, progress_style::automatic}}) {
    std::FILE* g = std::tmpfile();
    opt.out = g;
    {
      progress bar("quiet", 10, opt);
      for (int k = 0; k < 10; ++k) bar.advance();
    }
    CHECK(read_stream(g).empty());
    std::fclose(g);
  }
  // plain style with no interval: whole lines, then the final "done" line.
  std::FILE* h = std::tmpfile();
  {
    progress bar("cells", 4, {false, progress_style::plain, h, std::chrono::milliseconds(0), std::chrono::milliseconds(0)});
    for (int k = 0; k < 4; ++k) bar.advance();
  }
  const std::string plain = read_stream(h);
  std::fclose(h);
  CHECK(plain.find('\r') == std::string::npos);
  CHECK(contains(plain, "cells:  25.0%  1/4  elapsed"));
  CHECK(contains(plain, "cells: done 100.0%  4/4  elapsed"));
  CHECK(plain.back() == '\n');
}

TEST_CASE("progress: a job predicted to run long says so once, from its measured rate") {
  using qrm::io::progress;
  using qrm::io::progress_options;
  using qrm::io::progress_style;
  using ms = std::chrono::milliseconds;
  auto run = [](progress_options o, std::uint64_t total) {
    std::FILE* f = std::tmpfile();
    o.out = f;
    {
      progress bar("render", total, o);
      std::this_thread::sleep_for(ms(20));
      for (int k = 0; k < 3; ++k) bar.advance();  // 3 units in >= 20 ms: >= 6.6 s for 1000
    }
    std::string text = read_stream(f);
    std::fclose(f);
    return text;
  };
  // Predicted >= 6.6 s, threshold 1 s: one line, in both styles.
  for (progress_style style : {progress_style::plain, progress_style::terminal}) {
    progress_options o{false, style, nullptr, ms(0), ms(100000), ms(1000), ms(10)};
    const std::string text = run(o, 1000);
    CHECK(contains(text, "render: this will take about "));
    CHECK(contains(text, " in all (predicted from 1 of 1000 done in "));
    CHECK(text.find("this will take") == text.rfind("this will take"));
  }
  // Below the threshold, before the calibration time, when quiet, or when disabled: nothing.
  CHECK(!contains(run({false, progress_style::plain, nullptr, ms(0), ms(100000), ms(3600000), ms(10)}, 1000), "take about"));
  CHECK(!contains(run({false, progress_style::plain, nullptr, ms(0), ms(100000), ms(1000), ms(60000)}, 1000), "take about"));
  CHECK(!contains(run({true, progress_style::plain, nullptr, ms(0), ms(100000), ms(1000), ms(10)}, 1000), "take about"));
  CHECK(!contains(run({false, progress_style::plain, nullptr, ms(0), ms(100000), ms(0), ms(10)}, 1000), "take about"));
}
