// Space mesh of the 3-D Euler panel case: the box of fluid_box.geo meshed coarsely with curved
// cubic tetrahedra (order 3 is set by the case file); every fluid node rides inside one of
// its elements. The physical-group names are the fluid mesh's.
SetFactory("OpenCASCADE");

x_in = 0.0; x_le = 0.25; x_te = 0.75; x_out = 1.0;
height = 0.4; z_side = 0.5; half_span = 0.25;
h_panel = 0.1; h_far = 0.2;

Box(1) = {x_in, 0, 0, x_out - x_in, height, z_side};
Rectangle(100) = {x_le, 0, 0, x_te - x_le, half_span};
Rotate {{1, 0, 0}, {x_le, 0, 0}, Pi / 2} { Surface{100}; }
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

MeshSize{ PointsOf{ Volume{:}; } } = h_far;
MeshSize{ PointsOf{ Surface{panel[]}; } } = h_panel;
