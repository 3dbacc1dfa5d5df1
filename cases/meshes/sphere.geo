// Ball of radius 1 centred at (0, 0, 1): it touches the plane z = 0 at the origin. 4-node
// tetrahedra; the lower hemisphere is the physical group "contact".
// Regenerate: gmsh -3 sphere.geo -o sphere.msh   (Gmsh 4.8; MSH 4.1 ASCII)
lc = 0.4;
Point(1) = {0, 0, 1, lc};        // centre
Point(2) = {0, 0, 0, lc / 3};    // south pole
Point(3) = {1, 0, 1, lc};
Point(4) = {0, 1, 1, lc};
Point(5) = {-1, 0, 1, lc};
Point(6) = {0, -1, 1, lc};
Point(7) = {0, 0, 2, lc};        // north pole
// Equator and meridians.
Circle(1) = {3, 1, 4};
Circle(2) = {4, 1, 5};
Circle(3) = {5, 1, 6};
Circle(4) = {6, 1, 3};
Circle(5) = {2, 1, 3};
Circle(6) = {2, 1, 4};
Circle(7) = {2, 1, 5};
Circle(8) = {2, 1, 6};
Circle(9) = {7, 1, 3};
Circle(10) = {7, 1, 4};
Circle(11) = {7, 1, 5};
Circle(12) = {7, 1, 6};
// Lower octants.
Curve Loop(1) = {5, 1, -6};   Surface(1) = {1};
Curve Loop(2) = {6, 2, -7};   Surface(2) = {2};
Curve Loop(3) = {7, 3, -8};   Surface(3) = {3};
Curve Loop(4) = {8, 4, -5};   Surface(4) = {4};
// Upper octants.
Curve Loop(5) = {9, 1, -10};  Surface(5) = {5};
Curve Loop(6) = {10, 2, -11}; Surface(6) = {6};
Curve Loop(7) = {11, 3, -12}; Surface(7) = {7};
Curve Loop(8) = {12, 4, -9};  Surface(8) = {8};
Surface Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8};
Volume(1) = {1};
Physical Surface("contact") = {1, 2, 3, 4};
Physical Volume("body") = {1};
Mesh.MshFileVersion = 4.1;
