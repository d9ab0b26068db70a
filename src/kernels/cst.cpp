// Constant-strain tetrahedron kernels; see cst.hpp and doc/element.md.
#include <fdem/kernels/cst.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>
#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include <fdem/kernels/error.hpp>
#include <fdem/kernels/gather.hpp>

#include "cst_batch.hpp"
#include "materials/table.hpp"

namespace fdem::kernels {

// ---------------------------------------------------------------- the batched loop
// (cst_batch.hpp)
namespace {

template <class Model>
void StressPoint(const MaterialCoeffs &c, const double *F, double J, const double *D, double *T) {
  double pre[2] = {0, 0};
  if (Model::kSmallStrain || J > 0) Model::Prepare(J, pre);
  Model::Stress(c, F, J, pre, D, T);
}

// Kinematics, stress and nodal forces of one element into a TetState (false if skipped).
bool ToTetState(const double *T, const double *fe, const Extra &ex, int st, TetState &out) {
  out = TetState{};
  for (int r = 0; r < 3; ++r)
    for (int cc = 0; cc < 3; ++cc) out.F(r, cc) = ex.F[3 * r + cc], out.L(r, cc) = ex.L[3 * r + cc];
  const int idx[3][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}};
  for (int r = 0; r < 3; ++r)
    for (int cc = 0; cc < 3; ++cc) out.D(r, cc) = ex.D[idx[r][cc]], out.T(r, cc) = T[idx[r][cc]];
  out.J = ex.J;
  for (int a = 0; a < 4; ++a) out.force[a] = {fe[3 * a], fe[3 * a + 1], fe[3 * a + 2]};
  if (st == 1) {
    out.T = Mat3{};
    out.force = {};
    return false;
  }
  return st == 0;
}

template <class Model>
bool EvaluateOne(const TetElement &el, const MaterialCoeffs &c, const double *x, const double *v, TetState &out) {
  double T[6] = {0, 0, 0, 0, 0, 0}, fe[12] = {0};
  Extra ex{};
  const int st = v ? Core<Model, true>(el, c, x, v, T, fe, &ex) : Core<Model, false>(el, c, x, v, T, fe, &ex);
  return ToTetState(T, fe, ex, st, out);
}

// The Cauchy stress of one element alone (false if J <= 0): the same values as EvaluateOne's T,
// without its nodal forces and TetState.
template <class Model>
bool CellStressOne(const TetElement &el, const MaterialCoeffs &c, const double *x, const double *v, double *T) {
  Kin k;
  Kinematics<Model>(el, x, k);
  if (!(k.J > 0)) return false;
  double F[9], D[6] = {0, 0, 0, 0, 0, 0};
  DeformationGradient(k.c, el.Xinv, F);
  if (v) {
    double V[12], L[9];
    for (int a = 0; a < 4; ++a)
      for (int j = 0; j < 3; ++j) V[3 * a + j] = v[3 * el.n[a] + j];
    VelocityGradient<Model>(V, k.A, k.detC, el.Xinv, L, D);
  }
  Model::Stress(c, F, k.J, k.pre, D, T);
  return true;
}

template <class Model>
MaterialModel Entry() {
  return {Model::kName, Model::kSmallStrain, Model::kCost, &StressPoint<Model>, &Model::Energy, &EvaluateOne<Model>,
          &CellStressOne<Model>, &Batch<Model, true>, &Batch<Model, false>};
}

std::string MatName(const Material &m) { return "material '" + m.name + "'"; }

} // namespace

const std::vector<MaterialModel> &MaterialModels() {
  // Order matches MaterialModelId; the rows are those of materials/table.hpp.
#define FDEM_MATERIAL_ENTRY(M) Entry<M>(),
  static const std::vector<MaterialModel> table = {FDEM_MATERIAL_TABLE(FDEM_MATERIAL_ENTRY)};
#undef FDEM_MATERIAL_ENTRY
  return table;
}

int FindMaterialModel(const std::string &name) {
  const auto &t = MaterialModels();
  for (std::size_t i = 0; i < t.size(); ++i)
    if (name == t[i].name) return static_cast<int>(i);
  return -1;
}

void CheckMaterial(const Material &m) {
  auto num = [](double d) {
    std::ostringstream o;
    o << d;
    return o.str();
  };
  if (!(m.E > 0) || !std::isfinite(m.E))
    throw InputError(MatName(m) + ": Young's modulus E = " + num(m.E) + " must be positive and finite");
  if (!(m.nu > -1.0 && m.nu < 0.5))
    throw InputError(MatName(m) + ": Poisson's ratio nu = " + num(m.nu) + " must satisfy -1 < nu < 0.5");
  if (!(m.rho > 0) || !std::isfinite(m.rho))
    throw InputError(MatName(m) + ": density rho = " + num(m.rho) + " must be positive and finite");
  if (!(m.mu_visc >= 0) || !std::isfinite(m.mu_visc))
    throw InputError(MatName(m) + ": viscosity mu = " + num(m.mu_visc) + " must be >= 0 and finite");
  if (m.model < 0 || m.model >= static_cast<int>(MaterialModels().size()))
    throw InputError(MatName(m) + ": unknown material model " + std::to_string(m.model));
}

MaterialCoeffs MakeCoeffs(const Material &m) {
  CheckMaterial(m);
  MaterialCoeffs c;
  c.c_dev = m.E / (1.0 + m.nu);
  c.c_vol = m.E / (1.0 - 2.0 * m.nu);
  c.c_visc = 2.0 * m.mu_visc;
  c.G = 0.5 * c.c_dev;
  c.K = c.c_vol / 3.0;
  c.lambda = m.E * m.nu / ((1.0 + m.nu) * (1.0 - 2.0 * m.nu));
  return c;
}

// ---------------------------------------------------------------- elements
ElementData BuildElementData(const std::vector<Vec3> &X, const std::vector<std::array<int, 4>> &tets,
                             const std::vector<Material> &materials, const std::vector<int> &tet_material,
                             const std::vector<int> &tet_body) {
  if (materials.empty()) throw InputError("BuildElementData: no materials given");
  if (!tet_material.empty() && tet_material.size() != tets.size())
    throw InputError("BuildElementData: " + std::to_string(tet_material.size()) + " material indices for " +
                     std::to_string(tets.size()) + " tetrahedra");
  if (!tet_body.empty() && tet_body.size() != tets.size())
    throw InputError("BuildElementData: " + std::to_string(tet_body.size()) + " body ids for " +
                     std::to_string(tets.size()) + " tetrahedra");
  ElementData d;
  d.materials = materials;
  for (const auto &m : materials) d.coeffs.push_back(MakeCoeffs(m));
  d.body = tet_body.empty() ? std::vector<int>(tets.size(), 0) : tet_body;
  d.elems.reserve(tets.size()); // (each record written whole below: no zeroing pass first)
  for (std::size_t t = 0; t < tets.size(); ++t) {
    auto where = [&] { return "body " + std::to_string(d.body[t]) + ", element " + std::to_string(t); };
    TetElement el;
    el.n = tets[t];
    for (int a = 0; a < 4; ++a)
      if (el.n[a] < 0 || el.n[a] >= static_cast<int>(X.size()))
        throw InputError(where() + ": node index " + std::to_string(el.n[a]) + " out of range [0, " +
                         std::to_string(X.size()) + ")");
    el.material = tet_material.empty() ? 0 : tet_material[t];
    if (el.material < 0 || el.material >= static_cast<int>(materials.size()))
      throw InputError(where() + ": material index " + std::to_string(el.material) + " out of range");
    const Vec3 X0 = X[el.n[0]];
    const Mat3 Xe = Mat3::columns(X[el.n[1]] - X0, X[el.n[2]] - X0, X[el.n[3]] - X0);
    const double dX = det(Xe);
    double h2 = 0; // the longest edge (one square root: the root of the largest square is the largest root)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) h2 = std::max(h2, dot(X[el.n[a]] - X[el.n[b]], X[el.n[a]] - X[el.n[b]]));
    const double h = std::sqrt(h2);
    if (!(dX > 1e-12 * h * h * h)) {
      std::ostringstream o;
      o << where() << ": reference volume " << dX / 6.0
        << (dX < 0 ? " is negative (need det[X1-X0, X2-X0, X3-X0] > 0; OrientTets fixes the ordering)"
                   : " is zero (degenerate tetrahedron)");
      throw InputError(o.str());
    }
    const Mat3 Xi = inverse(Xe);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) el.Xinv[3 * r + c] = Xi(r, c);
    el.V0 = dX / 6.0;
    el.inv6V0 = 1.0 / dX;
    d.elems.push_back(el);
  }
  return d;
}

ElementData BuildElementData(const TetMesh &mesh, const std::vector<Material> &materials,
                             const std::vector<int> &material_of_body) {
  std::vector<int> mat(mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const int b = mesh.body.empty() ? 0 : mesh.body[t];
    if (b < 0 || b >= static_cast<int>(material_of_body.size()))
      throw InputError("body " + std::to_string(b) + ", element " + std::to_string(t) + ": no material given for this body");
    mat[t] = material_of_body[b];
  }
  return BuildElementData(mesh.nodes, mesh.tets, materials, mat, mesh.body);
}

std::int64_t ComputeInternalForces(const ElementData &data, const double *x, const double *v, double *f,
                                   std::size_t begin, std::size_t end) {
  end = std::min(end, data.elems.size());
  const auto &models = MaterialModels();
  std::int64_t first_bad = -1;
  const TetElement *E = data.elems.data();
  std::size_t i = begin;
  while (i < end) {
    // Run of elements sharing a material: one tight loop per run, which finds
    // the run's end itself (a separate scan read the element array twice).
    const int m = E[i].material;
    const MaterialModel &mm = models[data.materials[m].model];
    std::size_t done = 0;
    const std::int64_t bad =
        (v ? mm.batch : mm.batch_no_visc)(E + i, i, end - i, data.coeffs[m], x, v, f, &done);
    if (bad >= 0 && first_bad < 0) first_bad = bad;
    i += done;
  }
  return first_bad;
}

std::string InversionMessage(const ElementData &data, std::int64_t e, const double *x) {
  if (e < 0 || e >= static_cast<std::int64_t>(data.elems.size())) return "no inverted element";
  TetState s;
  EvaluateTet(data, static_cast<std::size_t>(e), x, nullptr, s);
  std::ostringstream o;
  o << "body " << (data.body.empty() ? 0 : data.body[e]) << ", element " << e << ": inverted (det F = " << s.J
    << " <= 0)";
  return o.str();
}

bool CellStress(const ElementData &data, std::size_t e, const double *x, const double *v, double T[6]) {
  const TetElement &el = data.elems[e];
  return MaterialModels()[data.materials[el.material].model].cell_stress(el, data.coeffs[el.material], x, v, T);
}

bool EvaluateTet(const ElementData &data, std::size_t e, const double *x, const double *v, TetState &out) {
  const TetElement &el = data.elems.at(e);
  return MaterialModels()[data.materials[el.material].model].evaluate(el, data.coeffs[el.material], x, v, out);
}

Mat3 CauchyStress(const Material &m, const Mat3 &F, const Mat3 &L) {
  const MaterialCoeffs c = MakeCoeffs(m);
  double Fa[9], D[6], T[6];
  for (int r = 0; r < 3; ++r)
    for (int cc = 0; cc < 3; ++cc) Fa[3 * r + cc] = F(r, cc);
  D[0] = L(0, 0), D[1] = L(1, 1), D[2] = L(2, 2);
  D[3] = 0.5 * (L(0, 1) + L(1, 0)), D[4] = 0.5 * (L(1, 2) + L(2, 1)), D[5] = 0.5 * (L(0, 2) + L(2, 0));
  const double J = det(F);
  if (!(J > 0) && !MaterialModels()[m.model].small_strain)
    throw InputError(MatName(m) + ": CauchyStress needs det F > 0");
  MaterialModels()[m.model].stress(c, Fa, J, D, T);
  Mat3 S;
  const int idx[3][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}};
  for (int r = 0; r < 3; ++r)
    for (int cc = 0; cc < 3; ++cc) S(r, cc) = T[idx[r][cc]];
  return S;
}

std::vector<double> NodalMasses(const ElementData &data, std::size_t n_nodes) {
  std::vector<double> m(n_nodes, 0.0);
  for (const auto &el : data.elems) {
    const double q = data.materials[el.material].rho * el.V0 / 4.0;
    for (int a = 0; a < 4; ++a) m.at(el.n[a]) += q;
  }
  return m;
}

} // namespace fdem::kernels
