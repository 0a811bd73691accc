
OPENQASM 3.0;
include "stdgates.inc";
// Written by qrm 0.1.0: 3 qubits, 2 ops, logical form: one line per gate, multiplexed gates one line per entry.
qubit[3] q;
ry(-0.78441406894056365) q[0];
ctrl @ negctrl @ z q[0], q[2], q[1];
