// An ellipse centred at the origin, major axis along x: the particle shape
// "ellipse".
//
// softpack.scene.shapes opens this file once per distinct size, after setting
// the ONELAB parameters below (metres, semi_major >= semi_minor) and the mesh
// options (one absolute element size, Frontal-Delaunay, linear triangles).
SetFactory("OpenCASCADE");
a = DefineNumber[2.0, Name "Parameters/semi_major"];
b = DefineNumber[1.0, Name "Parameters/semi_minor"];
Disk(1) = {0, 0, 0, a, b};
