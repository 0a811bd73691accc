// Scenes: the paper's data as the authors' code has it, the text format's round trip, and its errors.
#include <doctest/doctest.h>

#include <string>

#include <qrm/walk/paper_scenes.hpp>
#include <qrm/walk/scene_format.hpp>

#include "support/errors.hpp"

using qrm_test::error_of;

namespace {

const char* header2d = "qrm-scene 1\ndims 2\nsize 4\ncolor w 1 1 1\n";

}  // namespace

TEST_CASE("paper_8x8 holds the authors' data") {
  const qrm::scene s = qrm::paper_8x8();
  CHECK(s.size() == 8);
  CHECK(s.dims() == 2);
  // Spot checks typed in from the authors' tables (x = column, y = row).
  CHECK(s.at(0, 0).kind == qrm::material::boundary);
  CHECK(s.at(0, 0).normal_index == 3);
  CHECK(s.at(7, 0).normal_index == 5);
  CHECK(s.at(3, 4).kind == qrm::material::boundary);  // B0 in the middle
  CHECK(s.at(3, 4).normal_index == 0);
  CHECK(s.at(2, 3).kind == qrm::material::lambertian);
  CHECK(s.at(2, 3).normal_index == 7);
  CHECK(s.at(1, 1).kind == qrm::material::air);
  CHECK(s.at(0, 7).normal_index == 1);
  CHECK(s.at(3, 0).emission == qrm::rgb{1, 1, 1});
  CHECK(s.at(4, 4).emission == qrm::rgb{1, 1, 1});
  CHECK(s.at(3, 4).emission == qrm::rgb{0, 0, 0});
  CHECK(s.at(7, 3).emission == qrm::rgb{1, 1, 1});
  CHECK(s.at(1, 0).reflectance == qrm::rgb{0, 0.5, 0});     // G
  CHECK(s.at(7, 1).reflectance == qrm::rgb{0.5, 0, 0});     // R
  CHECK(s.at(2, 3).reflectance == qrm::rgb{0, 0, 0.5});     // Bl
  CHECK(s.at(0, 0).reflectance == qrm::rgb{0.75, 0.75, 0.75});  // Gy
  CHECK(s.at(1, 1).reflectance == qrm::rgb{1, 1, 1});       // A (air)
  std::size_t emitters = 0, air = 0;
  for (const auto& v : s.voxels()) {
    emitters += v.emission.r > 0;
    air += v.kind == qrm::material::air;
  }
  CHECK(emitters == 13);  // rows 0..7 of the emission table in examples/scenes/paper_8x8.txt: 2 + 1 + 1 + 2 + 3 + 1 + 1 + 2
  CHECK(air == 27);       // 64 minus 28 border cells minus the 3x3 block in the middle
}

TEST_CASE("paper_4x4 holds the authors' data") {
  const qrm::scene s = qrm::paper_4x4();
  CHECK(s.at(3, 0).normal_index == 5);
  CHECK(s.at(2, 0).emission == qrm::rgb{1, 1, 1});
  CHECK(s.at(0, 2).emission == qrm::rgb{1, 1, 1});
  CHECK(s.at(3, 1).reflectance == qrm::rgb{0.5, 0, 0});
  CHECK(s.at(1, 3).reflectance == qrm::rgb{0, 0, 0.5});
  CHECK(s.at(2, 3).reflectance == qrm::rgb{0, 0.5, 0});
  CHECK(s.at(1, 1).kind == qrm::material::air);
}

TEST_CASE("the built-in paper scenes equal their scene files in examples/scenes") {
  // The built-ins are C++ tables, the files scene-format text: two copies typed in from the
  // authors' tables, read through different code, so each checks the other.
  for (const char* name : {"paper_4x4", "paper_8x8"}) {
    CAPTURE(name);
    const qrm::scene file = qrm::load_scene(std::string(QRM_EXAMPLE_SCENES) + "/" + name + ".txt");
    const qrm::scene builtin = qrm::builtin_2d_scene(name);
    CHECK(builtin.name() == file.name());
    CHECK(builtin.size() == file.size());
    CHECK(builtin.march() == file.march());
    CHECK(builtin.lambertian_coin() == file.lambertian_coin());
    CHECK(builtin.voxels() == file.voxels());
  }
}

TEST_CASE("format_scene and parse_scene round-trip exactly, 2D and 3D") {
  const qrm::scene a = qrm::paper_8x8();
  const qrm::scene b = qrm::parse_scene(qrm::format_scene(a), "roundtrip");
  CHECK(a.voxels() == b.voxels());
  qrm::scene c("cube", 3, 4);
  c.at(1, 2, 3).kind = qrm::material::lambertian;
  c.at(1, 2, 3).normal = qrm::normalized({0.3, -0.2, 0.9});
  c.at(1, 2, 3).reflectance = {0.1, 0.2, 0.3};
  c.at(0, 0, 0).emission = {7.5, 0, 1e-3};
  const qrm::scene d = qrm::parse_scene(qrm::format_scene(c), "roundtrip3d");
  CHECK(c.voxels() == d.voxels());
  const qrm::scene e = qrm::parse_scene(
      "qrm-scene 1\ndims 3\nsize 4\ncolor red 0.6 0.1 0.1\nfill 0 0 0 3 0 3 L 0 1 0 rho red\nvoxel 1 1 1 air le 2 2 2\n", "fill");
  CHECK(e.at(3, 0, 2).kind == qrm::material::lambertian);
  CHECK(e.at(3, 0, 2).reflectance == qrm::rgb{0.6, 0.1, 0.1});
  CHECK(e.at(3, 1, 2).kind == qrm::material::air);
  CHECK(e.at(1, 1, 1).emission == qrm::rgb{2, 2, 2});
}

TEST_CASE("a 3D scene's camera block: parsed, defaults, written back exactly, refused where wrong") {
  const std::string head = "qrm-scene 1\ndims 3\nsize 4\nfill 0 0 0 3 0 3 L 0 1 0 rho 0.5 0.5 0.5\n";
  const qrm::scene plain = qrm::parse_scene(head, "plain");
  CHECK_FALSE(plain.view().has_value());
  const qrm::scene a = qrm::parse_scene(head + "camera look_at 2 0 2 position 2 3 -4.25\n", "cam");
  REQUIRE(a.view().has_value());
  CHECK(a.view()->position == qrm::vec3{2, 3, -4.25});
  CHECK(a.view()->look_at == qrm::vec3{2, 0, 2});
  CHECK(a.view()->up == qrm::vec3{0, 1, 0});           // the default
  CHECK(a.view()->vertical_fov_degrees == 39.3);       // the default
  const qrm::scene b = qrm::parse_scene(head + "camera position 0.1 0.2 0.3 look_at 1 1 1 up 0 0 1 fov 72.5\n", "cam2");
  CHECK(b.view()->up == qrm::vec3{0, 0, 1});
  CHECK(b.view()->vertical_fov_degrees == 72.5);
  const qrm::scene c = qrm::parse_scene(qrm::format_scene(b), "roundtrip");
  CHECK(c.view() == b.view());
  auto error = [&](const std::string& camera_line) {
    try {
      (void)qrm::parse_scene(head + camera_line + "\n", "bad.txt");
    } catch (const qrm::scene_parse_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  CHECK(error("camera position 0 0 0 look_at 0 0 0") == "bad.txt:5: camera: look_at equals position");
  CHECK(error("camera position 0 0 0 look_at 0 1 0") == "bad.txt:5: camera: up is zero or parallel to the view direction");
  CHECK(error("camera position 0 0 0 look_at 0 0 1 fov 0") == "bad.txt:5: camera: fov must be in (0, 180) degrees, got 0");
  CHECK(error("camera position 0 0 0 look_at 0 0 1 fov nan") == "bad.txt:5: fov: nan is not finite");
  CHECK(error("camera position 0 0 look_at 0 0 1").find("bad.txt:5: position: 'look_at' is not a number") == 0);
  CHECK(error("camera position 0 0 0 look_at 0 0 1 zoom 2").find("bad.txt:5: camera: unknown word 'zoom'") == 0);
  CHECK(error("camera position 0 0 0 position 1 1 1 look_at 0 0 1") == "bad.txt:5: camera: 'position' given twice");
  CHECK(error("camera position 0 0 0 look_at 0 0 1\ncamera position 0 0 0 look_at 0 0 1") ==
        "bad.txt:6: 'camera' given twice");
}

TEST_CASE("malformed scene files are rejected with the line and the problem") {
  auto err = [](const std::string& text) { return error_of([&] { qrm::parse_scene(text, "s.txt"); }); };
  CHECK(err("") == "s.txt:1: empty scene file (expected 'qrm-scene 1')");
  CHECK(err("qrm-scene 2\n").find("s.txt:1: unsupported format version '2'") == 0);
  CHECK(err("qrm-scene 1\ndims 4\n") == "s.txt:2: dims must be 2 or 3, got 4");
  CHECK(err("qrm-scene 1\ndims 2\nsize 6\n") == "s.txt:3: size must be a power of two in [2, 4096], got 6");
  CHECK(err("qrm-scene 1\nsize 4\n") == "s.txt:2: 'dims' must come before 'size'");
  CHECK(err(std::string(header2d) + "kinds\n. . . .\n. . . .\n") ==
        "s.txt:7: 'kinds' grid ends after 2 of 4 rows (started on line 5)");
  CHECK(err(std::string(header2d) + "kinds\n. . .\n") == "s.txt:6: 'kinds' row 0 has 3 tokens, expected 4");
  CHECK(err(std::string(header2d) + "kinds\n. X3 . .\n") ==
        "s.txt:6: unknown cell 'X3' at x = 1 (expected ., L<n>, B<n> or S<n>)");
  CHECK(err(std::string(header2d) + "kinds\n. L9 . .\n") == "s.txt:6: normal index must be 0..7, got 9");
  CHECK(err(std::string(header2d) + "voxel 1 1 L 2 rho 1.5 0 0\n") == "s.txt:5: reflectance 1.500000 outside [0, 1] in channel R");
  CHECK(err(std::string(header2d) + "voxel 1 1 L 2 rho 0.5 0.5 0.5 le 0 -1 0\n") ==
        "s.txt:5: emission -1.000000 is negative in channel G");
  CHECK(err(std::string(header2d) + "voxel 1 1 L 2 rho nan 0 0\n") == "s.txt:5: rho: nan is not finite");
  CHECK(err(std::string(header2d) + "voxel 1 1 L 2 rho 1 1 inf\n") == "s.txt:5: rho: inf is not finite");
  CHECK(err(std::string(header2d) + "voxel 9 1 air\n") == "s.txt:5: coordinate 9 outside the grid [0, 3]");
  CHECK(err(std::string(header2d) + "voxel 1 1 L 2\n") == "s.txt:5: a lambertian voxel needs 'rho C'");
  CHECK(err(std::string(header2d) + "emission\nw w w q\n") ==
        "s.txt:6: unknown colour 'q' (declare it with 'color q R G B')");
  CHECK(err(std::string(header2d) + "teleport 1 2\n") == "s.txt:5: unknown statement 'teleport'");
  CHECK(err("qrm-scene 1\ndims 2\n") == "s.txt:2: the file ends before 'size' (a scene needs 'dims' and 'size')");
  // The name becomes part of output file names: one plain word, else an error; without a name
  // line, the file's name without directory and extension.
  CHECK(err("qrm-scene 1\nname ../up\n") ==
        "s.txt:2: name may use only letters, digits, '_', '-' and '.' (it names the output files), got '../up'");
  CHECK(err("qrm-scene 1\nname a\"b\n").find("s.txt:2: name may use only") == 0);
  CHECK(qrm::parse_scene(std::string(header2d), "some/dir/my room.v2.txt").name() == "my_room.v2");
  CHECK(qrm::parse_scene(std::string(header2d), "C:\\scenes\\box.txt").name() == "box");
  CHECK(qrm::parse_scene(std::string(header2d) + "name box-2_b.c\n", "x/y.txt").name() == "box-2_b.c");
  CHECK(err("qrm-scene 1\ndims 3\nsize 4\nvoxel 1 1 1 L 0 0 0 rho 1 1 1\n") == "s.txt:4: normal must be a nonzero vector");
  // Found by fuzz_scene: a normal with a huge (or tiny) but finite component is a valid direction;
  // its length overflows (underflows) in double, which once escaped as std::invalid_argument.
  const qrm::scene huge = qrm::parse_scene("qrm-scene 1\ndims 3\nsize 4\nvoxel 1 1 1 S 0.5 0.5 1e300 rho 1 1 1\n", "s.txt");
  CHECK(huge.at(1, 1, 1).normal == qrm::vec3{0.5 / 1e300, 0.5 / 1e300, 1.0});
  const qrm::scene tiny = qrm::parse_scene("qrm-scene 1\ndims 3\nsize 4\nvoxel 1 1 1 L 3e-300 0 -4e-300 rho 1 1 1\n", "s.txt");
  CHECK(tiny.at(1, 1, 1).normal[0] == doctest::Approx(0.6).epsilon(1e-15));
  CHECK(tiny.at(1, 1, 1).normal[2] == doctest::Approx(-0.8).epsilon(1e-15));
  // ... and a normalized normal can have a subnormal component, which must read back (strtod
  // reports underflow for it): found by fuzz_scene as a failed format -> parse round trip.
  const qrm::scene sub = qrm::parse_scene("qrm-scene 1\ndims 3\nsize 4\nvoxel 1 1 1 S 1 0 5e-309 rho 1 1 1\n", "s.txt");
  CHECK(sub.at(1, 1, 1).normal[2] == 5e-309);
  CHECK(qrm::parse_scene(qrm::format_scene(sub), "again").voxels() == sub.voxels());
  CHECK(err("qrm-scene 1\ndims 3\nsize 4\nvoxel 1 1 1 S 1 0 1e999 rho 1 1 1\n") == "s.txt:4: normal: 1e999 is not finite");
  CHECK(error_of([] { qrm::load_scene("/nonexistent/scene.txt"); }) == "/nonexistent/scene.txt: cannot open the scene file");
  CHECK(error_of([] { qrm::scene("s", 2, 12); }) == "scene: size must be a power of two >= 2 (N = 2^P), got 12");
}

TEST_CASE("glossy voxels in scene files: kind G with 'lobe T', written back exactly, bad values refused") {
  const qrm::scene s = qrm::parse_scene(
      "qrm-scene 1\ndims 3\nsize 4\nvoxel 1 1 1 G 0 1 0 lobe 1.25 rho 0.9 0.9 0.9\nfill 2 2 2 2 2 3 glossy 1 0 0 lobe 0 "
      "rho 1 1 1\nvoxel 1 2 1 S 0 0 1 rho 0.5 0.5 0.5\n",
      "g.txt");
  CHECK(s.at(1, 1, 1).kind == qrm::material::glossy);
  CHECK(s.at(1, 1, 1).lobe == 1.25);
  CHECK(s.at(2, 2, 3).lobe == 0.0);
  CHECK(s.at(1, 2, 1).kind == qrm::material::specular);
  const std::string text = qrm::format_scene(s);
  CHECK(text.find(" G 0 1 0 lobe 1.25 rho") != std::string::npos);
  CHECK(qrm::parse_scene(text, "again").voxels() == s.voxels());
  // 2D: glossy voxel lines work; a grid cell has no room for the lobe.
  const qrm::scene s2 = qrm::parse_scene(std::string(header2d) + "voxel 1 1 G 2 lobe 0.5 rho w\n", "g2.txt");
  CHECK(s2.at(1, 1).lobe == 0.5);
  CHECK(qrm::parse_scene(qrm::format_scene(s2), "again").voxels() == s2.voxels());
  auto err = [](const std::string& text) { return error_of([&] { qrm::parse_scene(text, "s.txt"); }); };
  const std::string head3 = "qrm-scene 1\ndims 3\nsize 4\n";
  CHECK(err(head3 + "voxel 1 1 1 G 0 1 0 lobe -0.5 rho 1 1 1\n") ==
        "s.txt:4: lobe -0.5 outside [0, 4] (the glossy lobe parameter; 0 is a mirror)");
  CHECK(err(head3 + "voxel 1 1 1 G 0 1 0 lobe 4.5 rho 1 1 1\n") ==
        "s.txt:4: lobe 4.5 outside [0, 4] (the glossy lobe parameter; 0 is a mirror)");
  CHECK(err(head3 + "voxel 1 1 1 G 0 1 0 lobe nan rho 1 1 1\n") == "s.txt:4: lobe: nan is not finite");
  CHECK(err(head3 + "voxel 1 1 1 G 0 1 0 lobe\n") == "s.txt:4: 'lobe' needs a number in [0, 4]");
  CHECK(err(head3 + "voxel 1 1 1 G 0 1 0 rho 1 1 1\n") == "s.txt:4: a glossy voxel needs 'lobe T' (T in [0, 4]; 0 is a mirror)");
  CHECK(err(head3 + "voxel 1 1 1 S 0 1 0 lobe 1 rho 1 1 1\n") ==
        "s.txt:4: 'lobe' is the glossy lobe parameter; a specular voxel has none");
  CHECK(err(std::string(header2d) + "kinds\n. G2 . .\n") ==
        "s.txt:6: glossy cell 'G2' at x = 1: a grid cell has no room for the lobe; use a line 'voxel X Y G N lobe T rho C'");
  // Scenes built in code are checked too (walk_model validates).
  qrm::scene bad("bad", 3, 4);
  bad.at(1, 1, 1).kind = qrm::material::glossy;
  bad.at(1, 1, 1).normal = {0, 1, 0};
  bad.at(1, 1, 1).lobe = -1;
  CHECK(error_of([&] { bad.validate(); }) == "scene 'bad': voxel (1, 1, 1): lobe -1.000000 outside [0, 4] (the glossy lobe parameter)");
  bad.at(1, 1, 1).kind = qrm::material::lambertian;
  bad.at(1, 1, 1).lobe = 0.5;
  CHECK(error_of([&] { bad.validate(); }) ==
        "scene 'bad': voxel (1, 1, 1): lobe 0.500000 on a lambertian voxel (only glossy voxels have a lobe)");
  // In 2D the voxel is named by two coordinates, and only the failing voxel is named.
  qrm::scene flat("flat", 2, 4);
  flat.at(3, 2).reflectance = {0.5, 1.5, 0.5};
  CHECK(error_of([&] { flat.validate(); }) == "scene 'flat': voxel (3, 2): reflectance 1.500000 outside [0, 1] in channel G");
  flat.at(3, 2).reflectance = {0.5, 0.5, 0.5};
  flat.at(0, 1).emission = {0, 0, -1};
  CHECK(error_of([&] { flat.validate(); }) == "scene 'flat': voxel (0, 1): emission -1.000000 must be finite and >= 0 in channel B");
  flat.at(0, 1).emission = {0, 0, 0};
  flat.at(2, 3).kind = qrm::material::lambertian;
  flat.at(2, 3).normal_index = 9;
  CHECK(error_of([&] { flat.validate(); }) == "scene 'flat': voxel (2, 3): a lambertian voxel needs a normal index 0..7, got 9");
  flat.at(2, 3).normal_index = 1;
  CHECK_NOTHROW(flat.validate());
}
