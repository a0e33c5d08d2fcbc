// Space mesh of the panel-flutter case: the same slab as fluid_slab.geo, meshed
// coarsely with curved cubic tetrahedra (order 3 is set by the case file). Every
// fluid node rides inside one of its elements at fixed parametric coordinates.
// The physical-group names are the fluid mesh's.
SetFactory("Built-in");

x_in = 0.0; x_le = 0.25; x_te = 0.75; x_out = 1.0;
height = 0.4; width = 0.025;
h_panel = 0.1; h_far = 0.2;

Point(1) = {x_in, 0, 0, h_far};
Point(2) = {x_le, 0, 0, h_panel};
Point(3) = {x_te, 0, 0, h_panel};
Point(4) = {x_out, 0, 0, h_far};
Point(5) = {x_out, height, 0, h_far};
Point(6) = {x_in, height, 0, h_far};

Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Plane Surface(1) = {1};

ext[] = Extrude {0, 0, width} { Surface{1}; Layers{1}; };

Physical Surface("inflow") = {ext[7]};
Physical Surface("outflow") = {ext[5]};
Physical Surface("far_field") = {ext[6]};
Physical Surface("wall") = {ext[2], ext[4]};
Physical Surface("panel") = {ext[3]};
Physical Surface("symmetry") = {1, ext[0]};
Physical Volume("fluid") = {ext[1]};
