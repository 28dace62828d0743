// aries box 1 x 1 x 2 (the peer benchmark's compressed box, bench/peer.py): x, y in [0, 1], z in [0, 2].
// Physical groups are assigned by meshes/tools/build.py (bottom z=0, top z=2, side).
// Size: uniform target edge length h (-setnumber h X); build.py only passes preset values. HXT (Algorithm3D 10)
// meshes the 1M-tet size in about a minute where Delaunay takes several.
SetFactory("OpenCASCADE");
DefineConstant[ h = 0.1 ];
General.NumThreads = 1;
Box(1) = {0, 0, 0, 1, 1, 2};
Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.Algorithm3D = 10; // HXT
Mesh.Optimize = 1;
