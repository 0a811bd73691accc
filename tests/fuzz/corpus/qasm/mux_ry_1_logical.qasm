
OPENQASM 3.0;
include "stdgates.inc";
// Written by qrm 0.1.0: 4 qubits, 2 ops, logical form: one line per gate, multiplexed gates one line per entry.
qubit[4] q;
negctrl(2) @ ry(-1.5932513454078272) q[3], q[0], q[2];
ctrl @ negctrl @ ry(-2.8610182270292981) q[3], q[0], q[2];
ctrl @ negctrl @ ry(-0.9444537738867913) q[0], q[3], q[2];
ctrl(2) @ ry(-0.64050140005506395) q[3], q[0], q[2];
negctrl(3) @ ry(2.0608872913897454) q[0], q[1], q[2], q[3];
ctrl @ negctrl(2) @ ry(-2.2846853281585933) q[1], q[0], q[2], q[3];
ctrl(2) @ negctrl @ ry(2.4537394448097967) q[0], q[1], q[2], q[3];
ctrl @ negctrl(2) @ ry(-2.7820539281751691) q[2], q[0], q[1], q[3];
ctrl(2) @ negctrl @ ry(0.86648525156056744) q[0], q[2], q[1], q[3];
ctrl(2) @ negctrl @ ry(-2.4170417553644947) q[1], q[2], q[0], q[3];
ctrl(3) @ ry(2.3363014646268025) q[0], q[1], q[2], q[3];
