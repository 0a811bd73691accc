
OPENQASM 3.0;
include "stdgates.inc";
qubit[5] q;
ctrl @ h q[0], q[1];
negctrl @ ry(pi/3) q[1], q[2];
ctrl(2) @ negctrl(2) @ x q[0], q[1], q[2], q[3], q[4];
inv @ ctrl @ U(0.3, -0.2, 1.1) q[4], q[0];
ctrl @ inv @ negctrl @ s q[3], q[2], q[1];
inv @ inv @ t q[0];
ctrl @ gphase(pi / 2) q[3];
negctrl(3) @ gphase(-1.5) q[0], q[1], q[2];
ctrl @ ctrl @ cx q[0], q[1], q[2], q[3];
