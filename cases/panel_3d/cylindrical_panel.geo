// Shell mid-surface of the shallow cylindrical panel: the cylinder's axis runs along the
// flow (x), the panel spans 0.5 m along it (x from 0.25 to 0.75 m) and a chord of 0.5 m
// across it (z from -0.25 to 0.25 m), bulging into the flow (+y). Radius
// R = a^2 / (5 h) = 0.25 / (5 * 1.35e-3) = 37.037 m: curvature parameter a^2/(R h) = 5, a rise
// of 0.84 mm at mid-span (0.63 h). The edges lie in the plane y = 0. The arcs are Gmsh circle
// arcs, so the cubic triangles' edge and face nodes sit on the cylinder. Structured n x n grid
// (default 12), size_factor 0.5 doubles n.
SetFactory("Built-in");

x_le = 0.25; x_te = 0.75; half_chord = 0.25;
R = 0.25 / (5 * 1.35e-3);
yc = -Sqrt(R * R - half_chord * half_chord);  // the axis lies below the panel
n = Round(12 / Mesh.MeshSizeFactor);

Point(1) = {x_le, 0, -half_chord};
Point(2) = {x_le, 0, half_chord};
Point(3) = {x_te, 0, half_chord};
Point(4) = {x_te, 0, -half_chord};
Point(5) = {x_le, yc, 0};  // centres of the end arcs
Point(6) = {x_te, yc, 0};
Circle(1) = {1, 5, 2};  // leading edge (x = 0.25), an arc
Line(2) = {2, 3};       // side z = 0.25
Circle(3) = {3, 6, 4};  // trailing edge (x = 0.75), an arc
Line(4) = {4, 1};       // side z = -0.25
Curve Loop(1) = {1, 2, 3, 4};
Surface(1) = {1};  // ruled surface through the arcs: the cylinder
Transfinite Curve{1, 2, 3, 4} = n + 1;
Transfinite Surface{1};

Physical Curve("leading_edge") = {1};
Physical Curve("trailing_edge") = {3};
Physical Curve("sides") = {2, 4};
Physical Surface("panel") = {1};
