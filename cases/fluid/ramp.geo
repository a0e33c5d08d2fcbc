// Compression ramp (fluid-references.md b1), quasi-2-D slab one element thick: inflow at
// x = -0.25, flat wall y = 0 up to x = 0, ramp at theta_deg up to x = 1, outflow x = 1,
// free-stream top y = 1; symmetry planes z = 0 and z = h. Triangles extruded one layer
// without Recombine: each prism is 3 tetrahedra. Wrappers set theta_deg and h.
SetFactory("Built-in");
If (!Exists(theta_deg))
  theta_deg = 15;
EndIf
If (!Exists(h))
  h = 0.02;
EndIf
theta = theta_deg * Pi / 180;

Point(1) = {-0.25, 0, 0, h};
Point(2) = {0, 0, 0, h};
Point(3) = {1, Tan(theta), 0, h};
Point(4) = {1, 1, 0, h};
Point(5) = {-0.25, 1, 0, h};
Line(1) = {1, 2};  // flat wall
Line(2) = {2, 3};  // ramp
Line(3) = {3, 4};  // outflow
Line(4) = {4, 5};  // top
Line(5) = {5, 1};  // inflow
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};

ext[] = Extrude {0, 0, h} { Surface{1}; Layers{1}; };
// ext[0] = surface z = h, ext[1] = volume, ext[2..6] = side surfaces of lines 1..5.
Physical Surface("wall") = {ext[2], ext[3]};
Physical Surface("outflow") = {ext[4]};
Physical Surface("top") = {ext[5]};
Physical Surface("inflow") = {ext[6]};
Physical Surface("symmetry") = {1, ext[0]};
Physical Volume("fluid") = {ext[1]};
