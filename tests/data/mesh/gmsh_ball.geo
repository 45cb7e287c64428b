// Source of the gmsh_ball.* files: a ball of radius 10 with a 6x6x6 box (physical volume 2,
// "tumour") inside the rest (physical volume 1). Regenerate with Gmsh 4.8:
//   gmsh -3 gmsh_ball.geo -format msh22 -o gmsh_ball_v22.msh   (and msh41, vtk)
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 0, 10};
Box(2) = {-3, -3, -3, 6, 6, 6};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Physical Volume("tumour", 2) = {2};
Physical Volume("parenchyma", 1) = {3};
Physical Surface("skin", 10) = {1};
Mesh.CharacteristicLengthMax = 5;
