
OPENQASM 3.0;
include "stdgates.inc";
// Written by qrm 0.1.0: 4 qubits, 2 ops, logical form: one line per gate, multiplexed gates one line per entry.
qubit[4] q;
y q[0];
negctrl(3) @ x q[1], q[3], q[2], q[0];
