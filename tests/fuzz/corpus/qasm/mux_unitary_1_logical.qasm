
OPENQASM 3.0;
include "stdgates.inc";
// Written by qrm 0.1.0: 4 qubits, 2 ops, logical form: one line per gate, multiplexed gates one line per entry.
qubit[4] q;
gate qrm_unitary2_0 a0, a1 {
  ctrl @ U(0.83779451473817423, 3.1415926535897931, -3.1415926535897931) a1, a0;
  ctrl @ U(1.035965529251027, 0, -0) a0, a1;
  negctrl @ x a1, a0;
  negctrl @ U(0.92940847558310757, 0, -0) a0, a1;
  ctrl @ U(0.99225998686620165, 0, -0) a0, a1;
  negctrl @ x a1, a0;
  negctrl @ U(1.2341802617973103, 0, -0) a0, a1;
  negctrl @ U(2.2740045021865014, 3.1415926535897931, -3.1415926535897931) a1, a0;
}
gate qrm_unitary2_1 a0, a1 {
  ctrl @ U(0, 0, 3.1415926535897931) a1, a0;
  ctrl @ U(1.5707963267948968, 0, -0) a1, a0;
  ctrl @ U(1.2309594173407747, -3.1415926535897931, 3.1415926535897931) a0, a1;
  negctrl @ x a1, a0;
  negctrl @ U(1.0471975511965979, 0, -0) a0, a1;
  ctrl @ U(1.0471975511965979, 0, -0) a0, a1;
  negctrl @ x a1, a0;
  negctrl @ U(1.2309594173407747, 0, -0) a0, a1;
  negctrl @ U(1.5707963267948966, 0, -6.2831853071795862) a1, a0;
  negctrl @ gphase(3.1415926535897931) a1;
}
gate qrm_unitary2_2 a0, a1 {
  ctrl @ U(0, 0, 3.1415926535897931) a1, a0;
  ctrl @ U(1.5707963267948968, 0, -6.2831853071795862) a1, a0;
  ctrl @ gphase(3.1415926535897931) a1;
  ctrl @ U(1.2309594173407745, 3.1415926535897931, -3.1415926535897931) a0, a1;
  negctrl @ x a1, a0;
  negctrl @ U(3.1415926535897931, 3.1415926535897931, -3.1415926535897931) a0, a1;
  ctrl @ U(1.0471975511965979, -0, 0) a0, a1;
  negctrl @ x a1, a0;
  negctrl @ U(1.2309594173407747, -0, 0) a0, a1;
  negctrl @ U(1.5707963267948966, 0, 6.2831853071795862) a1, a0;
  negctrl @ gphase(-3.1415926535897931) a1;
}
ctrl @ negctrl @ qrm_unitary2_0 q[3], q[2], q[1], q[0];
ctrl @ negctrl @ qrm_unitary2_1 q[2], q[3], q[1], q[0];
ctrl(2) @ qrm_unitary2_2 q[3], q[2], q[1], q[0];
negctrl @ U(1.6830096858350601, 3.1415926535897931, -0) q[3], q[2];
ctrl @ U(1.6830096858350601, 3.1415926535897931, -0) q[3], q[2];
