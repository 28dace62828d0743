// Remesh a closed triangulated surface and fill it with tetrahedra (gmsh tutorial t13 recipe).
// Usage: gmsh -3 surface.msh remesh.geo -setnumber h X   (surface.msh is merged first)
// The input surface is split into parametrizable patches (ClassifySurfaces), turned into discrete
// geometry, remeshed with a uniform target edge length h, and the enclosed volume is meshed.
// Sharp features are not preserved (angle Pi): the scans are smooth, only the size matters here.
DefineConstant[ h = 0.05 ];
General.NumThreads = 1;
ClassifySurfaces{Pi, 0, 1, Pi};
CreateGeometry;
Surface Loop(1) = Surface{:};
Volume(1) = {1};
Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.Algorithm3D = 10; // HXT: fast for the large sizes, deterministic with one thread
Mesh.Optimize = 1;
