// Ball of radius R = 1 centred at (0, 0, R + gap) above a plate 1 x 1 x tp
// (top face z = 0), for the Hertz validation (tests/contact/test_contact_hertz.cpp,
// doc/contact_hertz.md). The mesh size is hc within rc of the ball's south pole
// (0, 0, gap), grows linearly to hf at distance rf, and is hf beyond.
// Physical volumes "ball" and "plate" become the two bodies.
//
//   gmsh -3 -format msh41 -setnumber hc 0.06 hertz_ball.geo -o hertz_ball_h06.msh
SetFactory("OpenCASCADE");
DefineConstant[ hc = {0.06, Name "size at the contact"},
                hf = {0.3,  Name "size far from the contact"},
                rc = {0.4,  Name "radius of the refined zone"},
                rf = {1.0,  Name "distance where the size reaches hf"},
                tp = {0.04, Name "plate thickness"},
                gap = {0.002, Name "initial gap"} ];
R = 1;
Sphere(1) = {0, 0, R + gap, R};
Box(2) = {-0.5, -0.5, -tp, 1.0, 1.0, tp};
Physical Volume("ball") = {1};
Physical Volume("plate") = {2};

// Size from the distance r to the contact point: hc for r < rc, then linear
// up to hf at r = rf; the same law in the plate. The plate is thin (its nodes are
// all fixed: only its top face matters) so that its tetrahedra, and their bounding
// spheres in the contact search, stay as small as the ball's at the contact.
Field[1] = MathEval;
Field[1].F = Sprintf("min(%g, %g + (%g - %g) * max(0, sqrt(x*x + y*y + (z - %g)^2) - %g) / (%g - %g))", hf, hc, hf, hc, gap, rc, rf, rc);
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;      // Frontal-Delaunay (surfaces)
Mesh.Algorithm3D = 1;    // Delaunay
Mesh.Optimize = 1;
