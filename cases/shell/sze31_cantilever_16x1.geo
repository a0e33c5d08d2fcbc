// Sze, Liu & Lo (2004) 3.1: cantilever plate strip under end shear. L = 10, b = 1 in the
// plane z = 0 (normal +z), clamped at x = 0, load on the free end x = 10. A structured
// 16 x 1 grid of quads, each split into two triangles; mesh it at order 3.
SetFactory("Built-in");
L = 10; b = 1; n_along = 16; n_across = 1;
Point(1) = {0, 0, 0};
Point(2) = {L, 0, 0};
Point(3) = {L, b, 0};
Point(4) = {0, b, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};  // free end
Line(3) = {3, 4};
Line(4) = {4, 1};  // clamped end
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = n_along + 1;
Transfinite Curve{2, 4} = n_across + 1;
Transfinite Surface{1};
Physical Curve("clamped") = {4};
Physical Curve("tip") = {2};
Physical Curve("sides") = {1, 3};  // long edges y = 0, y = b
Physical Surface("strip") = {1};
