// Shell mid-surface of the panel for the mesh-motion tests: the 0.5 m x 0.025 m strip of
// ../panel_flutter/panel_strip.geo (plane y = 0, x from 0.25 to 0.75 m, normal +y) as two
// halves meeting at x = 0.5 m, so that a load can act on each half: 2 x (10 x 1) quads split
// into triangles, 40 triangles, 244 nodes at order 3, like the flutter case's shell mesh.
SetFactory("Built-in");

x_le = 0.25; x_mid = 0.5; x_te = 0.75; width = 0.025;
n_half = 10; n_across = 1;

Point(1) = {x_le, 0, 0};
Point(2) = {x_le, 0, width};
Point(3) = {x_mid, 0, width};
Point(4) = {x_mid, 0, 0};
Point(5) = {x_te, 0, width};
Point(6) = {x_te, 0, 0};
Line(1) = {1, 2};  // leading edge (x = 0.25)
Line(2) = {2, 3};  // side z = width, upstream half
Line(3) = {3, 4};  // middle (x = 0.5)
Line(4) = {4, 1};  // side z = 0, upstream half
Line(5) = {3, 5};  // side z = width, downstream half
Line(6) = {5, 6};  // trailing edge (x = 0.75)
Line(7) = {6, 4};  // side z = 0, downstream half
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Curve Loop(2) = {-3, 5, 6, 7};
Plane Surface(2) = {2};
Transfinite Curve{1, 3, 6} = n_across + 1;
Transfinite Curve{2, 4, 5, 7} = n_half + 1;
Transfinite Surface{1};
Transfinite Surface{2};

Physical Curve("leading_edge") = {1};
Physical Curve("trailing_edge") = {6};
Physical Curve("sides") = {2, 4, 5, 7};
Physical Surface("upstream_half") = {1};
Physical Surface("downstream_half") = {2};
Physical Surface("panel") = {1, 2};
