// Unit cube meshed with tetrahedra, for the mesh-module tests.
SetFactory("Built-in");
h = 0.25;
Point(1) = {0, 0, 0, h};
Point(2) = {1, 0, 0, h};
Point(3) = {1, 1, 0, h};
Point(4) = {0, 1, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
ext[] = Extrude {0, 0, 1} { Surface{1}; };
Physical Surface("bottom") = {1};
Physical Surface("top") = {ext[0]};
Physical Surface("sides") = {ext[2], ext[3], ext[4], ext[5]};
Physical Volume("cube") = {ext[1]};
