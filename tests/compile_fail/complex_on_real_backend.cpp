// Must not compile with -DQRM_MUST_FAIL: a complex gate run on a real-valued backend.
#include <complex>

#include <qrm/qrm.hpp>

using out = qrm::output<>;
using L = qrm::layout<out>;

int main() {
  auto c = qrm::make_circuit<L>(qrm::h<out>{}, qrm::phase<out>{0.5});
#ifdef QRM_MUST_FAIL
  qrm::state_vector<double> s(L::width);
#else
  qrm::state_vector<std::complex<double>> s(L::width);
#endif
  qrm::run(s, c);
}
