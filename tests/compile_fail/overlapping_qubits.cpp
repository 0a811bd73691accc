// Must not compile with -DQRM_MUST_FAIL: a gate controlled by its own target.
#include <qrm/qrm.hpp>

using dir = qrm::direction<3>;
using L = qrm::layout<dir>;

int main() {
#ifdef QRM_MUST_FAIL
  qrm::x<qrm::bit<dir, 0>, qrm::on<qrm::bit<dir, 0>>> gate;  // control and target are one qubit
#else
  qrm::x<qrm::bit<dir, 0>, qrm::on<qrm::bit<dir, 1>>> gate;  // the twin: distinct qubits
#endif
  auto c = qrm::make_circuit<L>(gate);
  qrm::state_vector<double> s(L::width);
  qrm::run(s, c);
}
