#include "output.hpp"

#include <cstdio>

namespace fdem::output {

PetscErrorCode WriteReal(MPI_Comm comm, PetscViewer viewer, const char *name, const std::vector<PetscReal> &a, PetscInt bs) {
  Vec          V;
  PetscScalar *p;
  PetscFunctionBegin;
  PetscCall(VecCreate(comm, &V));
  PetscCall(VecSetSizes(V, (PetscInt)a.size(), PETSC_DETERMINE));
  PetscCall(VecSetBlockSize(V, bs));
  PetscCall(VecSetType(V, VECSTANDARD));
  PetscCall(PetscObjectSetName((PetscObject)V, name));
  PetscCall(VecGetArray(V, &p));
  for (size_t i = 0; i < a.size(); ++i) p[i] = a[i];
  PetscCall(VecRestoreArray(V, &p));
  PetscCall(VecView(V, viewer));
  PetscCall(VecDestroy(&V));
  PetscFunctionReturn(0);
}

PetscErrorCode WriteInt(MPI_Comm comm, PetscViewer viewer, const char *name, const std::vector<PetscInt> &a, PetscInt bs) {
  IS is;
  PetscFunctionBegin;
  PetscCall(ISCreateGeneral(comm, (PetscInt)a.size(), a.data(), PETSC_COPY_VALUES, &is));
  PetscCall(ISSetBlockSize(is, bs));
  PetscCall(PetscObjectSetName((PetscObject)is, name));
  PetscCall(ISView(is, viewer));
  PetscCall(ISDestroy(&is));
  PetscFunctionReturn(0);
}

PetscErrorCode WriteXDMF(MPI_Comm comm, const char *caller, const char *base, const char *grid, const char *topology, int npc, const std::vector<XdmfStep> &steps, const std::vector<XdmfAttribute> &attributes) {
  PetscMPIInt rank;
  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank != 0) PetscFunctionReturn(0);
  const std::string b(base), xmf = b + ".xmf";
  const size_t      slash = b.find_last_of('/');
  const std::string h5    = (slash == std::string::npos ? b : b.substr(slash + 1)) + ".h5"; // relative to the .xmf
  FILE             *fp    = std::fopen(xmf.c_str(), "w");
  PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "%s: cannot open %s for writing", caller, xmf.c_str());
  const int ip = (int)sizeof(PetscInt), rp = (int)sizeof(PetscReal);
  std::fprintf(fp, "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf xmlns:xi=\"http://www.w3.org/2001/XInclude\" Version=\"2.0\">\n  <Domain>\n");
  std::fprintf(fp, "    <Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Temporal\">\n", grid);
  for (const auto &o : steps) {
    char g[64];
    std::snprintf(g, sizeof(g), "step_%06d", (int)o.step);
    std::fprintf(fp, "      <Grid Name=\"%s\" GridType=\"Uniform\">\n", g);
    std::fprintf(fp, "        <Time Value=\"%.17g\"/>\n", (double)o.t);
    std::fprintf(fp, "        <Topology TopologyType=\"%s\" NumberOfElements=\"%lld\">\n", topology, o.ncell);
    std::fprintf(fp, "          <DataItem Dimensions=\"%lld %d\" NumberType=\"Int\" Precision=\"%d\" Format=\"HDF\">%s:/%s/cells</DataItem>\n        </Topology>\n", o.ncell, npc, ip, h5.c_str(), g);
    std::fprintf(fp, "        <Geometry GeometryType=\"XYZ\">\n");
    std::fprintf(fp, "          <DataItem Dimensions=\"%lld 3\" NumberType=\"Float\" Precision=\"%d\" Format=\"HDF\">%s:/%s/vertices</DataItem>\n        </Geometry>\n", o.nvert, rp, h5.c_str(), g);
    for (const auto &a : attributes) {
      const long long n = std::string(a.center) == "Node" ? o.nvert : o.ncell;
      char            dims[64];
      if (a.comps > 1 || !a.real) std::snprintf(dims, sizeof(dims), "%lld %d", n, a.comps); // ISView writes (n, 1)
      else std::snprintf(dims, sizeof(dims), "%lld", n);
      std::fprintf(fp, "        <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"%s\">\n", a.name, a.type, a.center);
      std::fprintf(fp, "          <DataItem Dimensions=\"%s\" NumberType=\"%s\" Precision=\"%d\" Format=\"HDF\">%s:/%s/%s</DataItem>\n        </Attribute>\n", dims, a.real ? "Float" : "Int", a.real ? rp : ip, h5.c_str(), g, a.name);
    }
    std::fprintf(fp, "      </Grid>\n");
  }
  std::fprintf(fp, "    </Grid>\n  </Domain>\n</Xdmf>\n");
  const bool ok = std::fclose(fp) == 0;
  PetscCheck(ok, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "%s: error writing %s", caller, xmf.c_str());
  PetscFunctionReturn(0);
}

} // namespace fdem::output
