// qrm/walk/scene_format.hpp: a small text format for scenes (2D and 3D), its parser and its writer.
//
//   # comment (to the end of the line)
//   qrm-scene 1                   first line: the format and its version
//   name my_scene                 optional
//   dims 2                        2 or 3
//   size 8                        N = 2^P voxels per axis
//   color W 1 1 1                 named colours for the statements below
//   kinds                         2D only: N rows (y = 0 first) of N tokens (x = 0 first):
//   B3 L4 ... B5                    .  air, L<n> Lambertian, B<n> boundary, S<n> specular,
//   ...                             n = normal index 0..7 (0 N, 1 NE, 2 E, ..., 7 NW); glossy
//                                   and medium cells need a lobe or a density, so they are
//                                   voxel lines, not grid cells
//   emission                      2D only: N rows of N colour names
//   reflectance                   2D only: N rows of N colour names
//   voxel X Y [Z] KIND [NORMAL] [lobe T | density P] [rho C] [le C]
//   fill X0 Y0 [Z0] X1 Y1 [Z1] KIND [NORMAL] [lobe T | density P] [rho C] [le C]  (inclusive box)
//                                 (rho is required for non-air voxels; le defaults to 0; lobe
//                                 is required for glossy voxels and refused for other kinds:
//                                 T in [0, 4], glossy_coin's lobe parameter, 0 = a mirror;
//                                 density is required for medium voxels (KIND M, no NORMAL)
//                                 and refused for other kinds: P in [0, 1], the probability of
//                                 scattering per voxel crossed; a medium's rho is the fraction
//                                 of light kept per voxel crossed, scatter or not)
//   march voxel|surface           optional: the walk this scene is made for: voxel (the paper's
//                                 one voxel per step) or surface (one bounce per step); the CLI
//                                 uses it unless --march says otherwise (default surface)
//   lambertian paper|symmetric    2D only, optional: the Lambertian coin: the paper's (default;
//                                 its lobe is one-sided about the normal) or the one symmetric
//                                 about the normal (a mirror-symmetric room, a symmetric map)
//   camera position X Y Z look_at X Y Z [up X Y Z] [fov DEGREES]
//                                 3D only: where the renderer looks from, in voxel units (voxel
//                                 (x, y, z) fills [x, x+1) x [y, y+1) x [z, z+1)); up defaults
//                                 to 0 1 0, fov (vertical, degrees, in (0, 180)) to 39.3. Without
//                                 it, 3D files of size >= 8 use the Cornell box's camera: at the
//                                 open -z side looking along +z, +y up, +x on the image's left.
//
// KIND is air, L, B, S, G or M (or lambertian, boundary, specular, glossy, medium); NORMAL is an index 0..7 in 2D
// and three numbers in 3D (normalised on reading); a colour C is a name or three numbers.
// Reflectance must lie in [0, 1]; emission must be finite and >= 0 (above 1 is fine: the walk
// circuit divides by the scene's largest emission and the estimate is scaled back). Every
// error names the file, the line and the problem.
#pragma once

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "scene.hpp"

namespace qrm {

struct scene_parse_error : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

namespace detail {

// A scene's name becomes part of output file names, so it is one plain file-name word.
template <int = 0>
inline bool scene_name_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
}
template <int = 0>
inline bool valid_scene_name(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), scene_name_char<>);
}

// The name of a scene file without a `name` line: its file name without directory and
// extension, other characters replaced by '_' ("my room.txt" -> "my_room").
template <int = 0>
inline std::string name_from_source(const std::string& source) {
  const auto slash = source.find_last_of("/\\");
  std::string stem = slash == std::string::npos ? source : source.substr(slash + 1);
  if (const auto dot = stem.rfind('.'); dot != std::string::npos && dot > 0) stem.erase(dot);
  std::replace_if(stem.begin(), stem.end(), [](char c) { return !scene_name_char(c); }, '_');
  return stem.empty() ? "scene" : stem;
}

class scene_parser {
 public:
  template <int = 0>
  scene_parser(std::string_view text, std::string source) : source_(std::move(source)) {
    std::string line;
    std::istringstream in{std::string(text)};
    while (std::getline(in, line)) {
      const auto hash = line.find('#');
      if (hash != std::string::npos) line.erase(hash);
      std::istringstream ls(line);
      std::vector<std::string> toks;
      for (std::string t; ls >> t;) toks.push_back(t);
      lines_.push_back(std::move(toks));
    }
  }

  template <int = 0>
  scene parse() {
    next_content_line();
    if (at_end()) fail("empty scene file (expected 'qrm-scene 1')");
    const auto& head = lines_[row_];
    if (head.size() != 2 || head[0] != "qrm-scene") fail("first line must be 'qrm-scene 1'");
    if (head[1] != "1") fail("unsupported format version '" + head[1] + "' (this reader knows version 1)");
    ++row_;
    std::string name = name_from_source(source_);
    unsigned dims = 0, size = 0;
    bool have_scene = false;
    scene s;
    for (next_content_line(); !at_end(); next_content_line()) {
      const auto& t = lines_[row_];
      const std::string& key = t[0];
      if (key == "name") {
        expect_count(t, 2, "name NAME");
        if (!valid_scene_name(t[1]))
          fail("name may use only letters, digits, '_', '-' and '.' (it names the output files), got '" + t[1] + "'");
        name = t[1];
        if (have_scene) s.set_name(name);
      } else if (key == "dims") {
        expect_count(t, 2, "dims 2|3");
        if (have_scene) fail("'dims' must come before any voxel data");
        dims = static_cast<unsigned>(integer(t[1], "dims"));
        if (dims != 2 && dims != 3) fail("dims must be 2 or 3, got " + t[1]);
      } else if (key == "size") {
        expect_count(t, 2, "size N");
        if (have_scene) fail("'size' given twice");
        if (dims == 0) fail("'dims' must come before 'size'");
        const long long n = integer(t[1], "size");
        if (n < 2 || n > 4096 || (n & (n - 1)) != 0) fail("size must be a power of two in [2, 4096], got " + t[1]);
        size = static_cast<unsigned>(n);
        s = scene(name, dims, size);
        have_scene = true;
      } else if (key == "color") {
        if (t.size() != 5) fail("expected 'color NAME R G B'");
        colors_[t[1]] = rgb{number(t[2], "color"), number(t[3], "color"), number(t[4], "color")};
      } else if (key == "kinds" || key == "emission" || key == "reflectance") {
        need_scene(have_scene, key);
        if (dims != 2) fail("'" + key + "' grids are for 2D scenes; use voxel/fill lines in 3D");
        expect_count(t, 1, key);
        read_grid(s, key);
        continue;  // read_grid leaves row_ on the next unread line
      } else if (key == "voxel" || key == "fill") {
        need_scene(have_scene, key);
        read_voxels(s, t, key == "fill");
      } else if (key == "march") {
        need_scene(have_scene, key);
        if (t.size() != 2 || (t[1] != "voxel" && t[1] != "surface")) fail("expected 'march voxel' or 'march surface'");
        if (s.march()) fail("'march' given twice");
        s.set_march(t[1] == "voxel" ? march_mode::voxel : march_mode::surface);
      } else if (key == "lambertian") {
        need_scene(have_scene, key);
        if (dims != 2) fail("'lambertian' chooses the 2D Lambertian coin; 3D coins have one form");
        if (t.size() != 2 || (t[1] != "paper" && t[1] != "symmetric"))
          fail("expected 'lambertian paper' or 'lambertian symmetric'");
        if (seen_lambertian_) fail("'lambertian' given twice");
        seen_lambertian_ = true;
        s.set_lambertian_coin(t[1] == "paper" ? lambertian_2d::paper : lambertian_2d::symmetric);
      } else if (key == "camera") {
        need_scene(have_scene, key);
        if (dims != 3) fail("'camera' is for 3D scenes (a 2D scene is a light map, not seen through a camera)");
        if (s.view()) fail("'camera' given twice");
        s.set_view(read_camera(t));
      } else {
        fail("unknown statement '" + key + "'");
      }
      ++row_;
    }
    if (!have_scene) fail_at(last_line(), "the file ends before 'size' (a scene needs 'dims' and 'size')");
    try {
      s.validate();
    } catch (const std::invalid_argument& e) {
      throw scene_parse_error(source_ + ": " + e.what());
    }
    return s;
  }

 private:
  bool at_end() const { return row_ >= lines_.size(); }
  std::size_t last_line() const { return lines_.empty() ? 0 : lines_.size() - 1; }
  template <int = 0>
  void next_content_line() {
    while (row_ < lines_.size() && lines_[row_].empty()) ++row_;
  }
  [[noreturn]] void fail(const std::string& msg) const { fail_at(row_, msg); }
  [[noreturn]] void fail_at(std::size_t row, const std::string& msg) const {
    throw scene_parse_error(source_ + ":" + std::to_string(row + 1) + ": " + msg);
  }
  template <int = 0>
  void need_scene(bool have, const std::string& key) const {
    if (!have) fail("'" + key + "' before 'size' (declare dims and size first)");
  }
  template <int = 0>
  void expect_count(const std::vector<std::string>& t, std::size_t n, const std::string& form) const {
    if (t.size() != n) fail("expected '" + form + "'");
  }
  template <int = 0>
  long long integer(const std::string& s, const std::string& what) const {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(s.c_str(), &end, 10);
    if (errno != 0 || end == s.c_str() || *end != '\0') fail(what + ": '" + s + "' is not an integer");
    return v;
  }
  template <int = 0>
  double number(const std::string& s, const std::string& what) const {
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(s.c_str(), &end);
    // ERANGE is underflow (a subnormal or zero, which format_scene can write, e.g. a normalized
    // normal's tiny component: still a number) or overflow (inf: refused as not finite below).
    if ((errno != 0 && errno != ERANGE) || end == s.c_str() || *end != '\0') fail(what + ": '" + s + "' is not a number");
    if (!std::isfinite(v)) fail(what + ": " + s + " is not finite");
    return v;
  }
  template <int = 0>
  rgb color_named(const std::string& n) const {
    auto it = colors_.find(n);
    if (it == colors_.end()) fail("unknown colour '" + n + "' (declare it with 'color " + n + " R G B')");
    return it->second;
  }
  template <int = 0>
  void check_reflectance(const rgb& c) const {
    for (int ch = 0; ch < 3; ++ch)
      if (!(c[ch] >= 0.0 && c[ch] <= 1.0))
        fail("reflectance " + std::to_string(c[ch]) + " outside [0, 1] in channel " + "RGB"[ch]);
  }
  template <int = 0>
  void check_emission(const rgb& c) const {
    for (int ch = 0; ch < 3; ++ch)
      if (!(c[ch] >= 0.0)) fail("emission " + std::to_string(c[ch]) + " is negative in channel " + "RGB"[ch]);
  }
  // KIND [NORMAL]: sets kind and normal; returns the next token index.
  template <int = 0>
  std::size_t read_kind(const std::vector<std::string>& t, std::size_t i, unsigned dims, voxel& v) const {
    if (i >= t.size()) fail("missing voxel kind (air, L, B, S, G or M)");
    const std::string& k = t[i++];
    if (k == "air" || k == ".") {
      v.kind = material::air;
      return i;
    }
    if (k == "L" || k == "lambertian") v.kind = material::lambertian;
    else if (k == "B" || k == "boundary") v.kind = material::boundary;
    else if (k == "S" || k == "specular") v.kind = material::specular;
    else if (k == "G" || k == "glossy") v.kind = material::glossy;
    else if (k == "M" || k == "medium") {
      v.kind = material::medium;
      return i;  // isotropic: no normal
    } else fail("unknown voxel kind '" + k + "' (air, L, B, S, G or M)");
    if (dims == 2) {
      if (i >= t.size()) fail("missing normal index after kind " + k);
      set_normal_2d(v, integer(t[i++], "normal"));
    } else {
      if (i + 3 > t.size()) fail("missing normal (three numbers) after kind " + k);
      const vec3 n{number(t[i], "normal"), number(t[i + 1], "normal"), number(t[i + 2], "normal")};
      i += 3;
      if (n[0] == 0 && n[1] == 0 && n[2] == 0) fail("normal must be a nonzero vector");
      // Unit normals are kept bit for bit, so format_scene -> parse_scene round-trips exactly.
      v.normal = std::abs(norm(n) - 1.0) < 1e-12 ? n : normalized(n);
    }
    return i;
  }
  template <int = 0>
  void set_normal_2d(voxel& v, long long n) const {
    if (n < 0 || n > 7) fail("normal index must be 0..7, got " + std::to_string(n));
    v.normal_index = static_cast<int>(n);
    v.normal = compass_vector_2d(v.normal_index);
  }
  // camera position X Y Z look_at X Y Z [up X Y Z] [fov DEGREES]
  template <int = 0>
  scene_view read_camera(const std::vector<std::string>& t) const {
    const char* form = "camera position X Y Z look_at X Y Z [up X Y Z] [fov DEGREES]";
    scene_view v;
    bool have_position = false, have_look_at = false, have_up = false, have_fov = false;
    auto triple = [&](std::size_t i, const std::string& what) {
      if (i + 3 > t.size()) fail("'" + what + "' needs three numbers (" + form + ")");
      return vec3{number(t[i], what), number(t[i + 1], what), number(t[i + 2], what)};
    };
    auto once = [&](bool& seen, const std::string& what) {
      if (seen) fail("camera: '" + what + "' given twice");
      seen = true;
    };
    for (std::size_t i = 1; i < t.size();) {
      const std::string& k = t[i];
      if (k == "position" || k == "look_at" || k == "up") {
        once(k == "position" ? have_position : k == "look_at" ? have_look_at : have_up, k);
        (k == "position" ? v.position : k == "look_at" ? v.look_at : v.up) = triple(i + 1, k);
        i += 4;
      } else if (k == "fov") {
        once(have_fov, k);
        if (i + 1 >= t.size()) fail("'fov' needs a number of degrees (" + std::string(form) + ")");
        v.vertical_fov_degrees = number(t[i + 1], "fov");
        if (!(v.vertical_fov_degrees > 0 && v.vertical_fov_degrees < 180))
          fail("camera: fov must be in (0, 180) degrees, got " + t[i + 1]);
        i += 2;
      } else {
        fail("camera: unknown word '" + k + "' (" + form + ")");
      }
    }
    if (!have_position || !have_look_at) fail(std::string("camera needs position and look_at (") + form + ")");
    const vec3 f{v.look_at[0] - v.position[0], v.look_at[1] - v.position[1], v.look_at[2] - v.position[2]};
    if (!(norm(f) > 0)) fail("camera: look_at equals position");
    const vec3 r{f[1] * v.up[2] - f[2] * v.up[1], f[2] * v.up[0] - f[0] * v.up[2], f[0] * v.up[1] - f[1] * v.up[0]};
    if (!(norm(r) > 1e-9 * norm(f) * norm(v.up))) fail("camera: up is zero or parallel to the view direction");
    return v;
  }
  template <int = 0>
  rgb read_color(const std::vector<std::string>& t, std::size_t& i, const std::string& what) const {
    if (i >= t.size()) fail("missing colour after '" + what + "'");
    if (colors_.count(t[i])) return colors_.at(t[i++]);
    if (i + 3 > t.size()) fail("'" + what + "' needs a colour name or three numbers");
    rgb c{number(t[i], what), number(t[i + 1], what), number(t[i + 2], what)};
    i += 3;
    return c;
  }
  template <int = 0>
  void read_voxels(scene& s, const std::vector<std::string>& t, bool box) {
    const unsigned d = s.dims();
    const std::size_t ncoord = box ? 2 * d : d;
    if (t.size() < 1 + ncoord) fail(std::string("expected ") + (box ? "fill X0 Y0 [Z0] X1 Y1 [Z1]" : "voxel X Y [Z]") + " KIND ...");
    long long c[6] = {};
    for (std::size_t k = 0; k < ncoord; ++k) {
      c[k] = integer(t[1 + k], "coordinate");
      if (c[k] < 0 || c[k] >= static_cast<long long>(s.size()))
        fail("coordinate " + t[1 + k] + " outside the grid [0, " + std::to_string(s.size() - 1) + "]");
    }
    voxel v;
    std::size_t i = read_kind(t, 1 + ncoord, d, v);
    bool rho_set = false, lobe_set = false, density_set = false;
    while (i < t.size()) {
      const std::string key = t[i++];
      if (key == "lobe") {
        if (v.kind != material::glossy)
          fail("'lobe' is the glossy lobe parameter; a " + std::string(material_name(v.kind)) + " voxel has none");
        if (i >= t.size()) fail("'lobe' needs a number in [0, 4]");
        v.lobe = number(t[i], "lobe");
        if (!(v.lobe >= 0.0 && v.lobe <= glossy_lobe_max))
          fail("lobe " + t[i] + " outside [0, 4] (the glossy lobe parameter; 0 is a mirror)");
        ++i;
        lobe_set = true;
      } else if (key == "density") {
        if (v.kind != material::medium)
          fail("'density' is a medium's scattering probability; a " + std::string(material_name(v.kind)) +
               " voxel has none");
        if (i >= t.size()) fail("'density' needs a number in [0, 1]");
        v.density = number(t[i], "density");
        if (!(v.density >= 0.0 && v.density <= 1.0))
          fail("density " + t[i] + " outside [0, 1] (the probability of scattering per voxel crossed)");
        ++i;
        density_set = true;
      } else if (key == "rho") {
        v.reflectance = read_color(t, i, "rho");
        check_reflectance(v.reflectance);
        rho_set = true;
      } else if (key == "le") {
        v.emission = read_color(t, i, "le");
        check_emission(v.emission);
      } else {
        fail("unexpected '" + key + "' (expected rho, le or, for glossy voxels, lobe, for medium voxels, density)");
      }
    }
    if (!rho_set && v.kind != material::air) fail("a " + std::string(material_name(v.kind)) + " voxel needs 'rho C'");
    if (!lobe_set && v.kind == material::glossy) fail("a glossy voxel needs 'lobe T' (T in [0, 4]; 0 is a mirror)");
    if (!density_set && v.kind == material::medium)
      fail("a medium voxel needs 'density P' (P in [0, 1]: the probability of scattering per voxel crossed)");
    long long lo[3] = {c[0], c[1], d == 3 ? c[2] : 0}, hi[3] = {lo[0], lo[1], lo[2]};
    if (box) {
      for (unsigned a = 0; a < d; ++a) hi[a] = c[d + a];
      for (unsigned a = 0; a < d; ++a)
        if (hi[a] < lo[a]) fail("fill box is empty (a max coordinate is below its min)");
    }
    for (long long z = lo[2]; z <= hi[2]; ++z)
      for (long long y = lo[1]; y <= hi[1]; ++y)
        for (long long x = lo[0]; x <= hi[0]; ++x)
          s.at(static_cast<unsigned>(x), static_cast<unsigned>(y), static_cast<unsigned>(z)) = v;
  }
  template <int = 0>
  void read_grid(scene& s, const std::string& key) {
    const unsigned n = s.size();
    const std::size_t header = row_;
    ++row_;
    for (unsigned y = 0; y < n; ++y) {
      next_content_line();
      if (at_end())
        fail_at(last_line(), "'" + key + "' grid ends after " + std::to_string(y) + " of " + std::to_string(n) +
                                   " rows (started on line " + std::to_string(header + 1) + ")");
      const auto& t = lines_[row_];
      if (t.size() != n)
        fail("'" + key + "' row " + std::to_string(y) + " has " + std::to_string(t.size()) + " tokens, expected " +
             std::to_string(n));
      for (unsigned x = 0; x < n; ++x) {
        voxel& v = s.at(x, y);
        const std::string& tok = t[x];
        if (key == "kinds") {
          if (tok == ".") {
            v.kind = material::air;
            v.normal_index = -1;
            v.normal = {0, 0, 0};
            continue;
          }
          const char k = tok[0];
          if (k == 'L') v.kind = material::lambertian;
          else if (k == 'B') v.kind = material::boundary;
          else if (k == 'S') v.kind = material::specular;
          else if (k == 'G')
            fail("glossy cell '" + tok + "' at x = " + std::to_string(x) +
                 ": a grid cell has no room for the lobe; use a line 'voxel X Y G N lobe T rho C'");
          else if (k == 'M')
            fail("medium cell '" + tok + "' at x = " + std::to_string(x) +
                 ": a grid cell has no room for the density; use a line 'voxel X Y M density P rho C'");
          else fail("unknown cell '" + tok + "' at x = " + std::to_string(x) + " (expected ., L<n>, B<n> or S<n>)");
          set_normal_2d(v, integer(tok.substr(1), "normal of cell '" + tok + "'"));
        } else if (key == "emission") {
          v.emission = color_named(tok);
          check_emission(v.emission);
        } else {
          v.reflectance = color_named(tok);
          check_reflectance(v.reflectance);
        }
      }
      ++row_;
    }
  }

  std::string source_;
  std::vector<std::vector<std::string>> lines_;
  std::size_t row_ = 0;
  std::map<std::string, rgb> colors_;
  bool seen_lambertian_ = false;
};

template <int = 0>
inline std::string format_double(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
}  // namespace detail

// parse_scene(text, source): a scene from the text format; `source` names it in errors.
template <int = 0>
scene parse_scene(std::string_view text, const std::string& source = "scene") {
  return detail::scene_parser(text, source).parse();
}

// load_scene(path): read and parse a scene file.
template <int = 0>
scene load_scene(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw scene_parse_error(path + ": cannot open the scene file");
  std::ostringstream ss;
  ss << f.rdbuf();
  return parse_scene(ss.str(), path);
}

// format_scene(s): the scene in the text format, one voxel line per non-default voxel
// (lossless: numbers are written with 17 significant digits).
template <int = 0>
std::string format_scene(const scene& s) {
  using detail::format_double;
  std::string out = "qrm-scene 1\nname " + (s.name().empty() ? std::string("unnamed") : s.name()) + "\ndims " +
                    std::to_string(s.dims()) + "\nsize " + std::to_string(s.size()) + "\n";
  const voxel plain_air{};
  for (std::size_t i = 0; i < s.voxel_count(); ++i) {
    const voxel& v = s[i];
    if (v == plain_air) continue;
    const auto c = s.coords(i);
    out += "voxel " + std::to_string(c[0]) + " " + std::to_string(c[1]);
    if (s.dims() == 3) out += " " + std::to_string(c[2]);
    switch (v.kind) {
      case material::air: out += " air"; break;
      case material::lambertian: out += " L"; break;
      case material::boundary: out += " B"; break;
      case material::specular: out += " S"; break;
      case material::glossy: out += " G"; break;
      case material::medium: out += " M"; break;
    }
    if (v.kind != material::air && v.kind != material::medium) {
      if (s.dims() == 2)
        out += " " + std::to_string(v.normal_index);
      else
        out += " " + format_double(v.normal[0]) + " " + format_double(v.normal[1]) + " " + format_double(v.normal[2]);
    }
    if (v.kind == material::glossy) out += " lobe " + format_double(v.lobe);
    if (v.kind == material::medium) out += " density " + format_double(v.density);
    out += " rho " + format_double(v.reflectance.r) + " " + format_double(v.reflectance.g) + " " +
           format_double(v.reflectance.b);
    out += " le " + format_double(v.emission.r) + " " + format_double(v.emission.g) + " " + format_double(v.emission.b);
    out += "\n";
  }
  if (const auto& m = s.march()) out += std::string("march ") + march_name(*m) + "\n";
  if (s.lambertian_coin() != lambertian_2d::paper) out += std::string("lambertian ") + lambertian_2d_name(s.lambertian_coin()) + "\n";
  if (const auto& v = s.view()) {
    auto triple = [](const vec3& a) { return format_double(a[0]) + " " + format_double(a[1]) + " " + format_double(a[2]); };
    out += "camera position " + triple(v->position) + " look_at " + triple(v->look_at) + " up " + triple(v->up) +
           " fov " + format_double(v->vertical_fov_degrees) + "\n";
  }
  return out;
}

}  // namespace qrm

// This header's part of <qrm/walk/compiled_walk.hpp> (QRM_COMPILED_WALK).
#define QRM_DETAIL_SCENE_FORMAT_INSTANCES(PREFIX)                    \
  PREFIX scene parse_scene<0>(std::string_view, const std::string&); \
  PREFIX scene load_scene<0>(const std::string&);                    \
  PREFIX std::string format_scene<0>(const scene&);
#ifdef QRM_COMPILED_WALK
namespace qrm {
QRM_DETAIL_SCENE_FORMAT_INSTANCES(extern template)
}  // namespace qrm
#endif
