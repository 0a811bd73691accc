
OPENQASM 3.0;
include "stdgates.inc";
qubit[1] q;
gate a0 x { h x; }
gate a1 x { a0 x; a0 x; }
gate a2 x { a1 x; a1 x; }
gate a3 x { a2 x; a2 x; }
gate a4 x { a3 x; a3 x; }
a4 q[0];
ry(((((((((1)))))))))  q[0];
