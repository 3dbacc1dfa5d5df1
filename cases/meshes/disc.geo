// Disc of radius 1 centred at (0, 1): it touches the plane y = 0 at the origin. 6-node triangles
// refined towards the pole; the lower half of the circle is the physical group "contact".
// Regenerate: gmsh -2 disc.geo -o disc.msh   (Gmsh 4.8; MSH 4.1 ASCII)
lc = 0.25;
Point(1) = {0, 1, 0, lc};        // centre
Point(2) = {0, 0, 0, lc / 5};    // pole
Point(3) = {1, 1, 0, lc};
Point(4) = {0, 2, 0, lc};
Point(5) = {-1, 1, 0, lc};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Circle(3) = {4, 1, 5};
Circle(4) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("contact") = {4, 1};
Physical Surface("body") = {1};
Mesh.ElementOrder = 2;
Mesh.MshFileVersion = 4.1;
