// Remesh an open triangulated surface (gmsh tutorial t13 recipe, 2D only).
// Usage: gmsh -2 surface.msh remesh_surface.geo -setnumber h X   (surface.msh is merged first)
// The input surface is split into parametrizable patches (ClassifySurfaces, boundary curves
// included), turned into discrete geometry and remeshed with a uniform target edge length h. The
// patches are remeshed conformingly, so the result has the input's topology (checked by build.py).
// Sharp features are not preserved (angle Pi): the scans are smooth, only the size matters here.
DefineConstant[ h = 0.05 ];
General.NumThreads = 1;
ClassifySurfaces{Pi, 1, 1, Pi};
CreateGeometry;
Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.Algorithm = 6; // Frontal-Delaunay
