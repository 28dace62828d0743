// aries cylinder (paper Fig. 6 pull / compress): axis along z, radius R, z in [0, L].
// Physical groups are assigned by meshes/tools/build.py (bottom z=0, top z=L, side).
// Size: uniform target edge length h (-setnumber h X); build.py only passes preset values.
SetFactory("OpenCASCADE");
DefineConstant[ h = 0.1, R = 0.5, L = 2.0 ];
General.NumThreads = 1;
Cylinder(1) = {0, 0, 0, 0, 0, L, R};
Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.Algorithm3D = 1; // Delaunay
Mesh.Optimize = 1;
