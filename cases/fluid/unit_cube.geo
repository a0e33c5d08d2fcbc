// Unit cube of N^3 structured hexahedra, each split into 6 tetrahedra (extrusions
// without Recombine), for the free-stream preservation case (fluid-references.md c1).
// One boundary group: the whole surface.
SetFactory("Built-in");
If (!Exists(N))
  N = 10;
EndIf
Point(1) = {0, 0, 0, 1.0};
line[] = Extrude {1, 0, 0} { Point{1}; Layers{N}; };
surface[] = Extrude {0, 1, 0} { Curve{line[1]}; Layers{N}; };
volume[] = Extrude {0, 0, 1} { Surface{surface[1]}; Layers{N}; };
Physical Surface("boundary") = Surface{:};
Physical Volume("fluid") = {volume[1]};
