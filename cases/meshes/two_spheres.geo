// Two balls of radius 1 touching at the origin (issue 24): body 1 (the slave) centred at
// (0, 0, 1) above, body 2 (the master) centred at (0, 0, -1) below. 4-node tetrahedra refined
// towards the poles; non-matching across the interface (pole sizes 0.13 and 0.16). Physical
// groups: "body1", "body2" (the volumes), "contact1", "contact2" (the hemispheres facing each
// other, the potential contact zone). The line of impact is the z axis.
// Regenerate: gmsh -3 two_spheres.geo -o two_spheres.msh   (Gmsh 4.8; MSH 4.1 ASCII)
lc = 0.5;
For b In {0:1}
  z = 1 - 2 * b;          // centre height: 1 (body 1), -1 (body 2)
  o = 1 - 2 * b;          // +1 above, -1 below: the near pole is at the origin
  hp = (b == 0) ? 0.13 : 0.16;
  p = 20 * b;
  Point(p + 1) = {0, 0, z, lc};          // centre
  Point(p + 2) = {0, 0, 0, hp};          // near pole
  Point(p + 3) = {1, 0, z, lc};
  Point(p + 4) = {0, 1, z, lc};
  Point(p + 5) = {-1, 0, z, lc};
  Point(p + 6) = {0, -1, z, lc};
  Point(p + 7) = {0, 0, z + o, lc};      // far pole
  Circle(p + 1) = {p + 3, p + 1, p + 4};
  Circle(p + 2) = {p + 4, p + 1, p + 5};
  Circle(p + 3) = {p + 5, p + 1, p + 6};
  Circle(p + 4) = {p + 6, p + 1, p + 3};
  Circle(p + 5) = {p + 2, p + 1, p + 3};
  Circle(p + 6) = {p + 2, p + 1, p + 4};
  Circle(p + 7) = {p + 2, p + 1, p + 5};
  Circle(p + 8) = {p + 2, p + 1, p + 6};
  Circle(p + 9) = {p + 7, p + 1, p + 3};
  Circle(p + 10) = {p + 7, p + 1, p + 4};
  Circle(p + 11) = {p + 7, p + 1, p + 5};
  Circle(p + 12) = {p + 7, p + 1, p + 6};
  Curve Loop(p + 1) = {p + 5, p + 1, -(p + 6)};   Surface(p + 1) = {p + 1};
  Curve Loop(p + 2) = {p + 6, p + 2, -(p + 7)};   Surface(p + 2) = {p + 2};
  Curve Loop(p + 3) = {p + 7, p + 3, -(p + 8)};   Surface(p + 3) = {p + 3};
  Curve Loop(p + 4) = {p + 8, p + 4, -(p + 5)};   Surface(p + 4) = {p + 4};
  Curve Loop(p + 5) = {p + 9, p + 1, -(p + 10)};  Surface(p + 5) = {p + 5};
  Curve Loop(p + 6) = {p + 10, p + 2, -(p + 11)}; Surface(p + 6) = {p + 6};
  Curve Loop(p + 7) = {p + 11, p + 3, -(p + 12)}; Surface(p + 7) = {p + 7};
  Curve Loop(p + 8) = {p + 12, p + 4, -(p + 9)};  Surface(p + 8) = {p + 8};
  Surface Loop(p + 1) = {p + 1, p + 2, p + 3, p + 4, p + 5, p + 6, p + 7, p + 8};
  Volume(p + 1) = {p + 1};
EndFor
Physical Volume("body1") = {1};
Physical Volume("body2") = {21};
Physical Surface("contact1") = {1, 2, 3, 4};
Physical Surface("contact2") = {21, 22, 23, 24};
Mesh.MshFileVersion = 4.1;
