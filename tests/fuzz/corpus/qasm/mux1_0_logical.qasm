
OPENQASM 3.0;
include "stdgates.inc";
// Written by qrm 0.1.0: 3 qubits, 2 ops, logical form: one line per gate, multiplexed gates one line per entry.
qubit[3] q;
negctrl @ ry(5.860985292782142) q[1], q[2];
ctrl @ h q[1], q[2];
negctrl(2) @ rz(4.446850509553002) q[2], q[0], q[1];
ctrl @ negctrl @ ry(-5.5083071074588714) q[2], q[0], q[1];
