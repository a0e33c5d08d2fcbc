// ~10 000-node shell for bench_shell: the Scordelis-Lo roof quarter (R = 25, half length
// 25, half-angle 40 deg) on 33 x 33 quads split into triangles; at order 3: 100 x 100 =
// 10 000 nodes, 2178 Tri10, 70 000 dofs. Groups as in cases/shell/scordelis_lo_*.geo.
SetFactory("Built-in");
R = 25; half_length = 25; angle = 40 * Pi / 180; n = 33;
Point(1) = {0, 0, R};
Point(2) = {half_length, 0, R};
Point(3) = {half_length, R * Sin(angle), R * Cos(angle)};
Point(4) = {0, R * Sin(angle), R * Cos(angle)};
Point(5) = {0, 0, 0};
Point(6) = {half_length, 0, 0};
Line(1) = {1, 2};
Circle(2) = {2, 6, 3};
Line(3) = {3, 4};
Circle(4) = {4, 5, 1};
Curve Loop(1) = {1, 2, 3, 4};
Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = n + 1;
Transfinite Surface{1};
Physical Curve("sym_y") = {1};
Physical Curve("sym_x") = {2};
Physical Curve("free") = {3};
Physical Curve("diaphragm") = {4};
Physical Surface("roof") = {1};
