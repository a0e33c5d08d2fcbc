// Fluid domain of the supersonic panel-flutter case: a quasi-2D slab.
// The x-y section 0 <= x <= 1 m, 0 <= y <= 0.4 m is meshed with triangles and
// extruded one layer in z (0 ... 0.025 m); with no Recombine each prism splits into
// three 4-node tetrahedra. The panel lies on y = 0 between x = 0.25 and 0.75 m.
// Sizes: h_panel near the panel, growing to h_far at the far-field boundary.
// shellflow scales every size by the case's size_factor (Mesh.MeshSizeFactor).
SetFactory("Built-in");

x_in = 0.0; x_le = 0.25; x_te = 0.75; x_out = 1.0;
height = 0.4; width = 0.025;
h_panel = 0.0088; h_wall = 0.0098; h_far = 0.0128;

Point(1) = {x_in, 0, 0, h_wall};
Point(2) = {x_le, 0, 0, h_panel};
Point(3) = {x_te, 0, 0, h_panel};
Point(4) = {x_out, 0, 0, h_wall};
Point(5) = {x_out, height, 0, h_far};
Point(6) = {x_in, height, 0, h_far};

Line(1) = {1, 2};  // wall upstream of the panel
Line(2) = {2, 3};  // panel
Line(3) = {3, 4};  // wall downstream of the panel
Line(4) = {4, 5};  // outflow
Line(5) = {5, 6};  // far field
Line(6) = {6, 1};  // inflow
Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Plane Surface(1) = {1};

ext[] = Extrude {0, 0, width} { Surface{1}; Layers{1}; };
// ext[0] = top surface (z = width), ext[1] = volume, ext[2..7] = side surfaces of lines 1..6.

Physical Surface("inflow") = {ext[7]};
Physical Surface("outflow") = {ext[5]};
Physical Surface("far_field") = {ext[6]};
Physical Surface("wall") = {ext[2], ext[4]};
Physical Surface("panel") = {ext[3]};
Physical Surface("symmetry") = {1, ext[0]};
Physical Volume("fluid") = {ext[1]};
