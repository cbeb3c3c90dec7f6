// A disk centred at the origin: the particle shape "disk".
//
// softpack.scene.mesh opens this file once per distinct size, after setting
// the ONELAB parameter "Parameters/radius" (metres) and the mesh options
// (one absolute element size, Frontal-Delaunay, linear triangles). The
// mesher expects ONE plane surface; its boundary nodes lie on the circle.
SetFactory("OpenCASCADE");
radius = DefineNumber[1.0, Name "Parameters/radius"];
Disk(1) = {0, 0, 0, radius, radius};
