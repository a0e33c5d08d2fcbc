// Space mesh of the shear-loaded strip: the channel of couette_channel.geo in coarse curved
// cubic tetrahedra (the order is set by the case file), with the fluid mesh's group names.
SetFactory("Built-in");

L = 0.1; H = 0.01; W = 0.004;

Point(1) = {0, 0, 0};
Point(2) = {L, 0, 0};
Point(3) = {L, H, 0};
Point(4) = {0, H, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = 6;
Transfinite Curve{2, 4} = 2;
Transfinite Surface{1};

ext[] = Extrude {0, 0, W} { Surface{1}; Layers{1}; };

Physical Surface("strip") = {ext[2]};
Physical Surface("outlet") = {ext[3]};
Physical Surface("lid") = {ext[4]};
Physical Surface("inlet") = {ext[5]};
Physical Surface("symmetry") = {1, ext[0]};
Physical Volume("fluid") = {ext[1]};
