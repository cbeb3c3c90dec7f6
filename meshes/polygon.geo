// A regular polygon centred at the origin, optionally with rounded corners:
// the particle shape "polygon".
//
// softpack.scene.shapes opens this file once per distinct size, after setting
// the ONELAB parameters below (metres) and the mesh options (one absolute
// element size, Frontal-Delaunay, linear triangles). One vertex (or rounded
// corner) points along +y. With corner_radius > 0 each corner is a circular
// arc tangent to its two sides: the polygon of apothem `apothem` offset
// inwards by the corner radius, then outwards by round arcs. The size
// (apothem) for a species' equal-area diameter is computed by the Python side.
n = DefineNumber[5, Name "Parameters/sides"];
apothem = DefineNumber[1.0, Name "Parameters/apothem"];
rc = DefineNumber[0.0, Name "Parameters/corner_radius"];

If (rc > 0)
  // arc centres at distance d from the origin, one per corner
  d = (apothem - rc) / Cos(Pi / n);
  For i In {0 : n - 1}
    t = Pi / 2 + 2 * Pi * i / n;
    Point(3 * i + 1) = {d * Cos(t), d * Sin(t), 0};
    Point(3 * i + 2) = {d * Cos(t) + rc * Cos(t - Pi / n),
                        d * Sin(t) + rc * Sin(t - Pi / n), 0};
    Point(3 * i + 3) = {d * Cos(t) + rc * Cos(t + Pi / n),
                        d * Sin(t) + rc * Sin(t + Pi / n), 0};
    Circle(2 * i + 1) = {3 * i + 2, 3 * i + 1, 3 * i + 3};
  EndFor
  For i In {0 : n - 1}
    j = (i + 1) % n;
    Line(2 * i + 2) = {3 * i + 3, 3 * j + 2};
  EndFor
  Curve Loop(1) = {1 : 2 * n};
Else
  R = apothem / Cos(Pi / n);
  For i In {0 : n - 1}
    t = Pi / 2 + 2 * Pi * i / n;
    Point(i + 1) = {R * Cos(t), R * Sin(t), 0};
  EndFor
  For i In {0 : n - 1}
    Line(i + 1) = {i + 1, (i + 1) % n + 1};
  EndFor
  Curve Loop(1) = {1 : n};
EndIf
Plane Surface(1) = {1};
