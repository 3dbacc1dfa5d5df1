// Two discs of radius 1 touching at the origin (issue 24): body 1 (the slave) centred at (0, 1)
// above, body 2 (the master) centred at (0, -1) below. 4-node quadrilaterals (recombined),
// graded towards the poles; non-matching across the interface (pole sizes 0.03 and 0.045).
// Physical groups: "body1", "body2" (the surfaces), "contact1", "contact2" (the arcs within 30
// degrees of each pole, the potential contact zone). The line of impact is the y axis.
// Regenerate: gmsh -2 two_discs.geo -o two_discs.msh   (Gmsh 4.8; MSH 4.1 ASCII)
lc = 0.4;
s = Sin(Pi / 6);
c = Cos(Pi / 6);
For b In {0:1}
  y = 1 - 2 * b;          // centre height: 1 (body 1), -1 (body 2)
  o = 1 - 2 * b;          // +1 above, -1 below: the pole is at the origin
  hp = (b == 0) ? 0.05 : 0.07;
  p = 10 * b;
  Point(p + 1) = {0, y, 0, lc};                  // centre
  Point(p + 2) = {0, 0, 0, hp};                  // pole
  Point(p + 3) = {s, y - o * c, 0, 3 * hp};      // end of the contact arc
  Point(p + 4) = {-s, y - o * c, 0, 3 * hp};
  Point(p + 5) = {0, y + o, 0, lc};              // antipode
  Circle(p + 1) = {p + 2, p + 1, p + 3};
  Circle(p + 2) = {p + 3, p + 1, p + 5};
  Circle(p + 3) = {p + 5, p + 1, p + 4};
  Circle(p + 4) = {p + 4, p + 1, p + 2};
  Curve Loop(p + 1) = {p + 1, p + 2, p + 3, p + 4};
  Plane Surface(p + 1) = {p + 1};
  Recombine Surface{p + 1};
EndFor
Physical Surface("body1") = {1};
Physical Surface("body2") = {11};
Physical Curve("contact1") = {4, 1};
Physical Curve("contact2") = {14, 11};
Mesh.Algorithm = 6;
Mesh.RecombinationAlgorithm = 3;
Mesh.SubdivisionAlgorithm = 1;
Mesh.MshFileVersion = 4.1;
