// The constant-strain tetrahedron with finite strain (Munjiza 2004, section
// 4.8, eqs 4.209-4.221; doc/book.md E), a compressible neo-Hookean variant
// and a small-strain linear tetrahedron, behind one batched internal-force
// kernel. See doc/element.md.
//
// Conventions
//  - A tetrahedron (n0,n1,n2,n3) must have det[X1-X0, X2-X0, X3-X0] > 0 in the
//    reference configuration (OrientTets in tetmesh.hpp fixes a mesh).
//  - Positions, velocities and forces are flat arrays, 3 doubles per node.
//  - ComputeInternalForces ACCUMULATES the internal (elastic + viscous) nodal
//    forces into f: f_i += -v T grad N_i = T a_i / 3 (a_i: outward area vector
//    of the face opposite node i). In uniform tension nodes are pulled toward
//    the element centroid; m a = f_internal + f_external.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <fdem/kernels/tetmesh.hpp>
#include <fdem/kernels/vec3.hpp>

namespace fdem::kernels {

// Material models; Material::model indexes MaterialModels().
enum MaterialModelId : int {
  kMunjizaCST = 0,        // book eq 4.220 (finite strain, Cauchy stress)
  kNeoHookean = 1,        // compressible neo-Hookean, for stretches beyond ~20%
  kSmallStrainLinear = 2  // linear tetrahedron: eps = sym(F) - I, reference geometry
};

struct Material {
  std::string name;
  double E = 0;        // Young's modulus
  double nu = 0;       // Poisson's ratio, -1 < nu < 0.5
  double rho = 0;      // density (reference configuration)
  double mu_visc = 0;  // viscosity coefficient of the 2 mu D term (not Lame's mu)
  int model = kMunjizaCST;
};

// Throws InputError naming the material if E <= 0, nu <= -1 or nu >= 0.5,
// rho <= 0, mu_visc < 0, a non-finite value or an unknown model.
void CheckMaterial(const Material &m);

// Derived coefficients used by the stress functions.
struct MaterialCoeffs {
  double c_dev;   // E/(1+nu)        = 2G
  double c_vol;   // E/(1-2nu)       = 3K
  double c_visc;  // 2 mu_visc
  double G, K, lambda;
};
MaterialCoeffs MakeCoeffs(const Material &m);  // checks m first

// Per-element data precomputed from the reference configuration.
struct TetElement {
  std::array<int, 4> n;  // node indices
  int material;          // index into ElementData::materials
  double Xinv[9];        // inverse of the reference edge matrix [X1-X0, X2-X0, X3-X0], row-major
  double V0;             // reference volume (> 0)
  double inv6V0;         // 1 / det[X1-X0, X2-X0, X3-X0]
};

struct ElementData {
  std::vector<TetElement> elems;
  std::vector<Material> materials;
  std::vector<MaterialCoeffs> coeffs;  // per material
  std::vector<int> body;               // body id per element (for messages)
  std::size_t size() const { return elems.size(); }
};

// Precompute element data. tet_material: material index per tetrahedron
// (empty: all use material 0); tet_body: body per tetrahedron (for messages;
// may be empty). Throws InputError naming body and element for a zero or
// negative reference volume or a bad node index, and naming the material for
// bad material parameters.
ElementData BuildElementData(const std::vector<Vec3> &X, const std::vector<std::array<int, 4>> &tets,
                             const std::vector<Material> &materials, const std::vector<int> &tet_material = {},
                             const std::vector<int> &tet_body = {});
// Convenience: material per body (material_of_body[mesh.body[t]]).
ElementData BuildElementData(const TetMesh &mesh, const std::vector<Material> &materials,
                             const std::vector<int> &material_of_body);

// Batched internal forces over elements [begin, end) (end = npos: all).
// x, v: current positions and velocities (3 per node); v may be nullptr (no
// viscous stress). Forces are ADDED to f. Returns the index of the first
// element with J = det F <= 0 (whose force is then skipped for the finite-strain
// models; the linear element still assembles it), or -1 if none.
std::int64_t ComputeInternalForces(const ElementData &data, const double *x, const double *v, double *f,
                                   std::size_t begin = 0, std::size_t end = static_cast<std::size_t>(-1));

// "body B, element E: inverted (det F = J <= 0)" for error reporting.
std::string InversionMessage(const ElementData &data, std::int64_t element, const double *x);

// One element, for tests and diagnostics: kinematics, Cauchy stress and the
// four nodal forces exactly as the batched kernel computes them.
struct TetState {
  Mat3 F;  // deformation gradient (eq 4.209-4.211)
  Mat3 L;  // velocity gradient w.r.t. current coordinates, = Fdot F^-1 (eq 4.212)
  Mat3 D;  // rate of deformation sym(L) (eq 4.216)
  Mat3 T;  // Cauchy stress
  double J;
  std::array<Vec3, 4> force;
};
// Returns false (and leaves T and force zero) if J <= 0 for a finite-strain model.
bool EvaluateTet(const ElementData &data, std::size_t e, const double *x, const double *v, TetState &out);
// Element e's Cauchy stress alone, T = (xx, yy, zz, xy, yz, xz): EvaluateTet's T to the bit (v:
// the node velocities of a viscous material, or nullptr). False, T untouched, if J <= 0.
bool CellStress(const ElementData &data, std::size_t e, const double *x, const double *v, double T[6]);
// The same for elements [begin, end) at once, element i's at T[6 (i - begin)] (NaN where J <= 0),
// with the internal-force kernel's batched loop (several elements an instruction): the same
// operations, so the same values but for round-off where that loop fuses multiply-adds.
void CellStresses(const ElementData &data, const double *x, const double *v, double *T, std::size_t begin, std::size_t end);

// Pointwise Cauchy stress of a material for deformation gradient F and
// velocity gradient L (for the linear model L is read as Fdot).
Mat3 CauchyStress(const Material &m, const Mat3 &F, const Mat3 &L = Mat3{});

// Lumped nodal masses rho V0 / 4 per element node.
std::vector<double> NodalMasses(const ElementData &data, std::size_t n_nodes);

// ---- material model registry ---------------------------------------------
// A model is one file in src/kernels/materials/ (its stress, strain energy and
// partition weight) plus one row in src/kernels/materials/table.hpp, from which
// this table (its functions and its instantiations of the batched loop) is
// built; see doc/architecture.md.
// A batch runs over elems[0, count) while the material stays that of elems[0]
// (the run is found on the way, in the cache lines the loop reads anyway) and
// stores in *done how many elements it took (>= 1).
using BatchFn = std::int64_t (*)(const TetElement *elems, std::size_t first, std::size_t count,
                                 const MaterialCoeffs &c, const double *x, const double *v, double *f,
                                 std::size_t *done);
// F row-major, D = (xx, yy, zz, xy, yz, xz), T likewise.
using StressFn = void (*)(const MaterialCoeffs &c, const double *F, double J, const double *D, double *T);
// Strain energy per reference volume at deformation gradient F (NaN if undefined).
using EnergyFn = double (*)(const MaterialCoeffs &c, const Mat3 &F);
// One element as EvaluateTet.
using EvaluateFn = bool (*)(const TetElement &el, const MaterialCoeffs &c, const double *x, const double *v, TetState &out);
// One element's stress as CellStress.
using CellStressFn = bool (*)(const TetElement &el, const MaterialCoeffs &c, const double *x, const double *v, double *T);
struct MaterialModel {
  const char *name;
  bool small_strain;
  int cost;  // relative cost in the internal-force kernel (bench/cst_kernel): the partition weight
  StressFn stress;
  EnergyFn energy;
  EvaluateFn evaluate;
  CellStressFn cell_stress;
  BatchFn batch;
  BatchFn batch_no_visc;
};
const std::vector<MaterialModel> &MaterialModels();
int FindMaterialModel(const std::string &name);  // -1 if unknown

} // namespace fdem::kernels
