// Fluid of the shear-loaded strip (couette_strip.yaml): a channel 0 <= x <= L, 0 <= y <= H,
// one cell layer 0 <= z <= W (symmetry planes), meshed structured: nx x ny rectangles, each
// split into two triangles, extruded one layer; each prism splits into three tetrahedra.
// The strip is the whole lower wall y = 0; the lid y = H moves at U; the ends x = 0 and x = L
// are far-field boundaries holding the Couette profile.
SetFactory("Built-in");

L = 0.1; H = 0.01; W = 0.004;
nx = 50; ny = 10;

Point(1) = {0, 0, 0};
Point(2) = {L, 0, 0};
Point(3) = {L, H, 0};
Point(4) = {0, H, 0};
Line(1) = {1, 2};  // strip (lower wall)
Line(2) = {2, 3};  // outlet end
Line(3) = {3, 4};  // lid
Line(4) = {4, 1};  // inlet end
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = nx + 1;
Transfinite Curve{2, 4} = ny + 1;
Transfinite Surface{1};

ext[] = Extrude {0, 0, W} { Surface{1}; Layers{1}; };
// ext[0] = z = W face, ext[1] = volume, ext[2..5] = the faces of lines 1..4.

Physical Surface("strip") = {ext[2]};
Physical Surface("outlet") = {ext[3]};
Physical Surface("lid") = {ext[4]};
Physical Surface("inlet") = {ext[5]};
Physical Surface("symmetry") = {1, ext[0]};
Physical Volume("fluid") = {ext[1]};
