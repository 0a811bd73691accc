// Must not compile with -DQRM_MUST_FAIL: a gate on a register that is not in the layout.
#include <qrm/qrm.hpp>

using dir = qrm::direction<3>;
using out = qrm::output<>;
using other = qrm::ancilla<"other", 1>;
using L = qrm::layout<dir, out>;

int main() {
#ifdef QRM_MUST_FAIL
  auto c = qrm::make_circuit<L>(qrm::x<other, qrm::on<dir>>{});
#else
  auto c = qrm::make_circuit<L>(qrm::x<out, qrm::on<dir>>{});
#endif
  qrm::state_vector<double> s(L::width);
  qrm::run(s, c);
}
