// The reference panel strip (coupling.md): 0.5 m x 0.025 m in the plane y = 0, from
// x = 0.25 to 0.75 m, 0 <= z <= 0.025 m; 20 x 1 quads split into triangles: 244 nodes at
// order 3. Both ends clamped, the long edges z = 0 and z = 0.025 are symmetry planes.
SetFactory("Built-in");
x_le = 0.25; x_te = 0.75; width = 0.025;
n_along = 20; n_across = 1;
Point(1) = {x_le, 0, 0};
Point(2) = {x_le, 0, width};
Point(3) = {x_te, 0, width};
Point(4) = {x_te, 0, 0};
Line(1) = {1, 2};  // leading edge (x = 0.25)
Line(2) = {2, 3};  // side z = width
Line(3) = {3, 4};  // trailing edge (x = 0.75)
Line(4) = {4, 1};  // side z = 0
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = n_across + 1;
Transfinite Curve{2, 4} = n_along + 1;
Transfinite Surface{1};
Physical Curve("leading_edge") = {1};
Physical Curve("trailing_edge") = {3};
Physical Curve("sides") = {2, 4};
Physical Surface("panel") = {1};
