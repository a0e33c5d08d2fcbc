// Shell mid-surface of the 3-D panel cases: a 0.5 m x 0.5 m plate in the plane y = 0,
// x from 0.25 to 0.75 m (the flow runs along +x), z from -0.25 to 0.25 m (mid-span z = 0).
// A structured n x n grid of quads, each split into two triangles; at the case's order 3
// the default 12 x 12 grid has 288 cubic triangles and 1 369 nodes. The grid follows the
// case's size_factor (Mesh.MeshSizeFactor): 0.5 doubles n. The loop runs so that the
// surface normal is +y, into the flow.
SetFactory("Built-in");

x_le = 0.25; x_te = 0.75; z_lo = -0.25; z_hi = 0.25;
n = Round(12 / Mesh.MeshSizeFactor);

Point(1) = {x_le, 0, z_lo};
Point(2) = {x_le, 0, z_hi};
Point(3) = {x_te, 0, z_hi};
Point(4) = {x_te, 0, z_lo};
Line(1) = {1, 2};  // leading edge (x = 0.25)
Line(2) = {2, 3};  // side z = 0.25
Line(3) = {3, 4};  // trailing edge (x = 0.75)
Line(4) = {4, 1};  // side z = -0.25
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = n + 1;
Transfinite Surface{1};

Physical Curve("leading_edge") = {1};
Physical Curve("trailing_edge") = {3};
Physical Curve("sides") = {2, 4};
Physical Surface("panel") = {1};
