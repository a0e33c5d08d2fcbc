// Fluid of the laminar boundary-layer case (boundary_layer_panel.yaml): the panel-flutter
// slab of ../panel_flutter/fluid_slab.geo (0 <= x <= 1 m, 0 <= y <= 0.4 m, one layer
// 0 <= z <= 0.025 m; the panel on y = 0 between x = 0.25 and 0.75 m) meshed structured and
// graded towards the wall: 100 cells along x (10 mm), 45 across with a growth ratio 1.13
// (first cell 0.21 mm, about 15 cells in the 9 mm layer at mid-panel). Each rectangle
// splits into two triangles, each prism of the layer into three tetrahedra. The case's
// size_factor f (Mesh.MeshSizeFactor) divides the cell counts by f and raises the growth
// ratio to the power f (f = 2: 50 x 23 cells, first cell 0.45 mm).
SetFactory("Built-in");

x_in = 0.0; x_le = 0.25; x_te = 0.75; x_out = 1.0;
height = 0.4; width = 0.025;
f = Mesh.MeshSizeFactor;
n_plate = Round(25 / f); n_panel = Round(50 / f); ny = Round(45 / f); growth = 1.13^f;

Point(1) = {x_in, 0, 0};
Point(2) = {x_le, 0, 0};
Point(3) = {x_te, 0, 0};
Point(4) = {x_out, 0, 0};
Point(5) = {x_out, height, 0};
Point(6) = {x_in, height, 0};

Line(1) = {1, 2};  // wall upstream of the panel (the plate starts at the inflow, x = 0)
Line(2) = {2, 3};  // panel
Line(3) = {3, 4};  // wall downstream of the panel
Line(4) = {4, 5};  // outflow
Line(5) = {5, 6};  // far field
Line(6) = {6, 1};  // inflow
Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = n_plate + 1;
Transfinite Curve{2} = n_panel + 1;
Transfinite Curve{5} = 2 * n_plate + n_panel + 1;
Transfinite Curve{4} = ny + 1 Using Progression growth;
Transfinite Curve{6} = ny + 1 Using Progression 1 / growth;
Transfinite Surface{1} = {1, 4, 5, 6};

ext[] = Extrude {0, 0, width} { Surface{1}; Layers{1}; };

Physical Surface("inflow") = {ext[7]};
Physical Surface("outflow") = {ext[5]};
Physical Surface("far_field") = {ext[6]};
Physical Surface("wall") = {ext[2], ext[4]};
Physical Surface("panel") = {ext[3]};
Physical Surface("symmetry") = {1, ext[0]};
Physical Volume("fluid") = {ext[1]};
