// Must not compile with -DQRM_MUST_FAIL: a compact state labelled by a 32-bit integer.
#include <cstdint>

#include <qrm/backends/compact.hpp>

int main() {
#ifdef QRM_MUST_FAIL
  qrm::compact_state<double, std::uint32_t> s(4);
#else
  qrm::compact_state<double, qrm::wide_label<1>> s(4);
#endif
  return static_cast<int>(s.nonzeros()) - 1;
}
