
OPENQASM 3.0;
include "stdgates.inc";
// Written by qrm 0.1.0: 3 qubits, 2 ops, logical form: one line per gate, multiplexed gates one line per entry.
qubit[3] q;
negctrl(2) @ U(1.4219349692463561, 1.2074431277087077, 3.3822404672257709) q[0], q[1], q[2];
negctrl(2) @ gphase(-2.7758137536133698) q[0], q[1];
ctrl @ negctrl @ U(1.4219349692463561, 1.2074431277087077, 3.3822404672257709) q[0], q[1], q[2];
ctrl @ negctrl @ gphase(-2.7758137536133698) q[0], q[1];
ctrl @ negctrl @ U(2.2559055840139814, 3.1415926535897931, -3.1415926535897931) q[1], q[0], q[2];
ctrl(2) @ U(1.4219349692463561, 1.2074431277087077, 3.3822404672257709) q[0], q[1], q[2];
ctrl(2) @ gphase(-2.7758137536133698) q[0], q[1];
negctrl @ U(0.90745916140604865, 3.1415926535897931, -3.1415926535897931) q[2], q[1];
