// Must not compile with -DQRM_MUST_FAIL: a control value that does not fit its register.
#include <qrm/qrm.hpp>

using dir = qrm::direction<3>;
using out = qrm::output<>;
using L = qrm::layout<dir, out>;

int main() {
#ifdef QRM_MUST_FAIL
  auto c = qrm::make_circuit<L>(qrm::x<out, qrm::when<dir, 8>>{});  // dir holds 0..7
#else
  auto c = qrm::make_circuit<L>(qrm::x<out, qrm::when<dir, 7>>{});
#endif
  qrm::state_vector<double> s(L::width);
  qrm::run(s, c);
}
