// Quasi-1-D shock tube for the fluid verification cases (fluid-references.md a1–a3, c2,
// c3, d1): the box [0, 1] x [0, 0.02] x [0, 0.02] with Nx structured columns; each
// column is one hexahedron split into 6 tetrahedra (extrusions without Recombine).
// Every node lies on the lateral faces, so the symmetry planes make the flow 1-D.
// Wrappers set Nx (and optionally width) and include this file (tube_nx200.geo, ...).
SetFactory("Built-in");
If (!Exists(Nx))
  Nx = 100;
EndIf
length = 1.0;
If (!Exists(width))
  width = 0.02;
EndIf

Point(1) = {0, 0, 0, 1.0};
line[] = Extrude {length, 0, 0} { Point{1}; Layers{Nx}; };
surface[] = Extrude {0, width, 0} { Curve{line[1]}; Layers{1}; };
volume[] = Extrude {0, 0, width} { Surface{surface[1]}; Layers{1}; };

eps = 1e-6;
left[] = Surface In BoundingBox {-eps, -eps, -eps, eps, width + eps, width + eps};
right[] = Surface In BoundingBox {length - eps, -eps, -eps, length + eps, width + eps, width + eps};
y0[] = Surface In BoundingBox {-eps, -eps, -eps, length + eps, eps, width + eps};
y1[] = Surface In BoundingBox {-eps, width - eps, -eps, length + eps, width + eps, width + eps};
z0[] = Surface In BoundingBox {-eps, -eps, -eps, length + eps, width + eps, eps};
z1[] = Surface In BoundingBox {-eps, -eps, width - eps, length + eps, width + eps, width + eps};

Physical Surface("left") = {left[]};
Physical Surface("right") = {right[]};
Physical Surface("sides") = {y0[], y1[], z0[], z1[]};
Physical Volume("fluid") = {volume[1]};
