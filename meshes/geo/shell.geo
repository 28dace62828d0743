// aries thick spherical shell (Lame's pressurized sphere): inner radius a, outer radius b, centred at the origin.
// Physical groups are assigned by meshes/tools/build.py (inner r = a, outer r = b).
// Size: uniform target edge length h (-setnumber h X); build.py only passes preset values.
SetFactory("OpenCASCADE");
DefineConstant[ h = 0.1, a = 0.5, b = 1.0 ];
General.NumThreads = 1;
Sphere(1) = {0, 0, 0, b};
Sphere(2) = {0, 0, 0, a};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.Algorithm3D = 1; // Delaunay
Mesh.Optimize = 1;
