
OPENQASM 3.0;
include "stdgates.inc";
// Written by qrm 0.1.0: 3 qubits, 2 ops, logical form: one line per gate, multiplexed gates one line per entry.
qubit[3] q;
negctrl(2) @ ry(-1.2931174383578232) q[1], q[2], q[0];
ctrl @ negctrl @ ry(-0.82054108660188763) q[1], q[2], q[0];
negctrl(2) @ ry(-0.84518970261785253) q[0], q[1], q[2];
ctrl @ negctrl @ ry(-1.5747162996828818) q[0], q[1], q[2];
ctrl(2) @ ry(-1.5116722161658473) q[0], q[1], q[2];
