// Fluid domain of the 3-D Euler panel case (clamped_square.yaml): a half model. The box
// 0 <= x <= 1 m (flow along +x), 0 <= y <= 0.4 m (the plate at y = 0), 0 <= z <= 0.5 m, with
// the symmetry plane z = 0 through the plate's mid-span. The half plate, x from 0.25 to 0.75 m
// and z from 0 to 0.25 m, is embedded in the wall y = 0; the box reaches 0.25 m past its side
// edge, so the flow passes around it. Sizes (docs/fluid.md, "Cells per wavelength"): h_panel
// within d_fine of the plate, growing linearly with the distance to h_far at d_far (a Gmsh
// Distance + Threshold size field); shellflow scales them by the case's size_factor
// (Mesh.MeshSizeFactor).
SetFactory("OpenCASCADE");

x_in = 0.0; x_le = 0.25; x_te = 0.75; x_out = 1.0;
height = 0.4; z_side = 0.5; half_span = 0.25;
h_panel = 0.0125; h_far = 0.05;
d_fine = 0.01; d_far = 0.1;

Box(1) = {x_in, 0, 0, x_out - x_in, height, z_side};
Rectangle(100) = {x_le, 0, 0, x_te - x_le, half_span};     // in the plane z = 0 ...
Rotate {{1, 0, 0}, {x_le, 0, 0}, Pi / 2} { Surface{100}; }  // ... turned into y = 0
BooleanFragments{ Volume{1}; Delete; }{ Surface{100}; Delete; }

e = 1e-6;
panel[] = Surface In BoundingBox{x_le - e, -e, -e, x_te + e, e, half_span + e};
bottom[] = Surface In BoundingBox{x_in - e, -e, -e, x_out + e, e, z_side + e};
wall[] = {};
For k In {0 : #bottom[] - 1}
  If (bottom[k] != panel[0])
    wall[] += bottom[k];
  EndIf
EndFor
Physical Surface("inflow") = Surface In BoundingBox{x_in - e, -e, -e, x_in + e, height + e, z_side + e};
Physical Surface("outflow") = Surface In BoundingBox{x_out - e, -e, -e, x_out + e, height + e, z_side + e};
top[] = Surface In BoundingBox{x_in - e, height - e, -e, x_out + e, height + e, z_side + e};
side[] = Surface In BoundingBox{x_in - e, -e, z_side - e, x_out + e, height + e, z_side + e};
Physical Surface("far_field") = {top[], side[]};
Physical Surface("wall") = {wall[]};
Physical Surface("panel") = {panel[]};
Physical Surface("symmetry") = Surface In BoundingBox{x_in - e, -e, -e, x_out + e, height + e, e};
Physical Volume("fluid") = Volume{:};

// The wall pressure of the plate is made in the cells next to it (the wavy-wall study of
// docs/fluid.md): they get h_panel; a disturbance of the plate leaves along its Mach lines and
// does not come back, so the cells grow away from it.
Field[1] = Distance;
Field[1].SurfacesList = {panel[]};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_panel;
Field[2].SizeMax = h_far;
Field[2].DistMin = d_fine;
Field[2].DistMax = d_far;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
