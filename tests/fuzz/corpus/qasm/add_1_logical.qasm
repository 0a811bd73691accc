
OPENQASM 3.0;
include "stdgates.inc";
// Written by qrm 0.1.0: 4 qubits, 2 ops, logical form: one line per gate, multiplexed gates one line per entry.
qubit[4] q;
gate qrm_add1_1 a0 {
  x a0;
}
qrm_add1_1 q[1];
negctrl @ qrm_add1_1 q[1], q[0];
