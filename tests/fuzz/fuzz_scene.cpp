// libFuzzer target: the scene parser must either return a valid scene or throw
// qrm::scene_parse_error -- never crash, hang, or throw anything else -- and a parsed scene must
// round-trip through format_scene exactly.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include <qrm/walk/scene_format.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  qrm::scene s;
  try {
    s = qrm::parse_scene(text, "fuzz");
  } catch (const qrm::scene_parse_error&) {
    return 0;  // rejected with a message: fine
  }
  // Accepted: it must validate and survive a round trip unchanged.
  s.validate();
  const qrm::scene again = qrm::parse_scene(qrm::format_scene(s), "roundtrip");
  if (!(again.voxels() == s.voxels()) || again.size() != s.size() || again.dims() != s.dims() || again.view() != s.view())
    std::abort();
  return 0;
}
