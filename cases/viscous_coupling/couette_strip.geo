// Shell mid-surface of the shear-loaded strip: 0 <= x <= L in the plane y = 0,
// 0 <= z <= W, a structured 10 x 1 grid of quads split into triangles (cubic: the case's
// order). The loop runs z-then-x so that the surface normal is +y, into the channel.
SetFactory("Built-in");

L = 0.1; W = 0.004;
n_along = 10;

Point(1) = {0, 0, 0};
Point(2) = {0, 0, W};
Point(3) = {L, 0, W};
Point(4) = {L, 0, 0};
Line(1) = {1, 2};  // upstream end (x = 0): clamped
Line(2) = {2, 3};  // side z = W
Line(3) = {3, 4};  // downstream end (x = L): free to slide
Line(4) = {4, 1};  // side z = 0
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = 2;
Transfinite Curve{2, 4} = n_along + 1;
Transfinite Surface{1};

Physical Curve("upstream_end") = {1};
Physical Curve("downstream_end") = {3};
Physical Curve("sides") = {2, 4};
Physical Surface("strip") = {1};
