// Must not compile with -DQRM_MUST_FAIL: a complex gate run on a real-valued compact backend.
#include <complex>

#include <qrm/qrm.hpp>

using out = qrm::output<>;
using L = qrm::layout<out>;

int main() {
  auto c = qrm::make_circuit<L>(qrm::h<out>{}, qrm::phase<out>{0.5});
#ifdef QRM_MUST_FAIL
  qrm::compact_state<double> s(L::width);
#else
  qrm::compact_state<std::complex<double>> s(L::width);
#endif
  qrm::run(s, c);
}
