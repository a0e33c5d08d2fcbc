// Shell mid-surface of the 2:1 rectangular panel: a = 0.5 m along the flow (x from 0.25 to
// 0.75 m) by b = 0.25 m across it (z from -0.125 to 0.125 m), in the plane y = 0, normal +y.
// A structured 2n x n grid of quads split into triangles (default n = 8: 256 cubic
// triangles, 1 225 nodes); size_factor 0.5 doubles n.
SetFactory("Built-in");

x_le = 0.25; x_te = 0.75; z_lo = -0.125; z_hi = 0.125;
n = Round(8 / Mesh.MeshSizeFactor);

Point(1) = {x_le, 0, z_lo};
Point(2) = {x_le, 0, z_hi};
Point(3) = {x_te, 0, z_hi};
Point(4) = {x_te, 0, z_lo};
Line(1) = {1, 2};  // leading edge (x = 0.25)
Line(2) = {2, 3};  // side z = 0.125
Line(3) = {3, 4};  // trailing edge (x = 0.75)
Line(4) = {4, 1};  // side z = -0.125
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = n + 1;
Transfinite Curve{2, 4} = 2 * n + 1;
Transfinite Surface{1};

Physical Curve("leading_edge") = {1};
Physical Curve("trailing_edge") = {3};
Physical Curve("sides") = {2, 4};
Physical Surface("panel") = {1};
