#include "run.hpp"

#include "builder.hpp"

#include <fdem/contact.h>
#include <fdem/deformable_contact.h>
#include <fdem/scene.h>
#include <petscts.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <csignal>
#include <ctime>
#include <sys/stat.h>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#include <sys/mman.h>
#endif

namespace fdem::driver {
namespace {

struct Progress {
  PetscLogDouble wall0 = 0, last = 0;
  PetscReal      end = 0;
  PetscInt       step0 = 0, bodies = 0;
  PetscBool      on = PETSC_TRUE, tty = PETSC_FALSE;
  PetscMPIInt    rank = 0;
};

// A run that inserts joints builds its models again at each insertion, the new model beside the
// old one until the state is handed over, and each rebuild's arrays land on memory the process
// has not touched before: a page fault per 4 KiB page, which costs 10-20 us on a virtual machine
// (a quarter of a rebuild on the crater, doc/fracture.md). So before the stepping the C library's
// heap gets room for `factor` times the memory in use (blocks of 16 MiB, allocated and freed at
// once: never touched, so they cost no memory until used), kept in the heap (no trimming, no
// separate mappings below 32 MiB, above which a single block would be one) and marked for transparent huge pages (2 MiB, one fault each) where the
// system offers them on request. Where it does not, or without glibc, nothing changes.
void ReserveHeapForRebuilds(double factor) {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || __GLIBC_MINOR__ >= 33) && defined(MADV_HUGEPAGE) // (mallinfo2: glibc 2.33)
  if (!(factor > 0)) return;
  const struct mallinfo2 mi    = mallinfo2();
  const double           bytes = factor * (double)mi.uordblks;
  if (!(bytes >= 4.0 * (1 << 20)) || bytes > 1e12) return;
  constexpr std::size_t piece = (std::size_t)16 << 20; // (below the mapping threshold: each piece from the heap)
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, INT_MAX);
  std::vector<void *> blocks;
  for (std::size_t got = 0; got < (std::size_t)bytes; got += piece) {
    void *block = std::malloc(piece);
    if (!block) break;
    blocks.push_back(block);
    const std::uintptr_t huge = (std::uintptr_t)2 << 20, a = ((std::uintptr_t)block + huge - 1) & ~(huge - 1), e = ((std::uintptr_t)block + piece) & ~(huge - 1);
    if (e > a) (void)madvise((void *)a, e - a, MADV_HUGEPAGE); // (EINVAL where the kernel has none: then 4 KiB pages)
  }
  for (void *block : blocks) std::free(block);
#else
  (void)factor;
#endif
}

PetscErrorCode ProgressMonitor(TS ts, PetscInt step, PetscReal t, Vec, void *ctx) {
  Progress      &p = *(Progress *)ctx;
  PetscLogDouble now;
  PetscFunctionBeginUser;
  if (!p.on || p.rank != 0) PetscFunctionReturn(0);
  PetscCall(PetscTime(&now));
  if (now - p.last < (p.tty ? 1.0 : 10.0)) PetscFunctionReturn(0);
  p.last                = now;
  const double el       = now - p.wall0, frac = p.end > 0 ? t / p.end : 1;
  const double rate     = el > 0 ? (step - p.step0) / el : 0;
  const double eta      = frac > 0 ? el * (1 - frac) / frac : 0;
  std::fprintf(stdout, "%st = %.5g s (%5.1f%%)  %.0f steps/s  %.3g body-steps/s  ETA %.0f s%s", p.tty ? "\r" : "", (double)t, 100 * frac, rate, rate * p.bodies, eta, p.tty ? "   " : "\n");
  std::fflush(stdout);
  (void)ts;
  PetscFunctionReturn(0);
}

// Inner <Grid ... GridType="Uniform"> ... </Grid> blocks of an XDMF file written by the library.
std::vector<std::string> UniformGrids(const std::string &file) {
  std::ifstream            in(file);
  std::stringstream        ss;
  std::vector<std::string> out;
  ss << in.rdbuf();
  const std::string s = ss.str();
  size_t            pos = 0;
  while ((pos = s.find("GridType=\"Uniform\"", pos)) != std::string::npos) {
    const size_t b = s.rfind("<Grid", pos), e = s.find("</Grid>", pos);
    if (b == std::string::npos || e == std::string::npos) break;
    out.push_back(s.substr(b, e + 7 - b));
    pos = e;
  }
  return out;
}

// dir/scene.xmf: one temporal collection whose every time is a spatial collection of the
// rigid skins (rigid.h5) and the meshes (mesh.h5): ParaView opens all bodies at once.
PetscErrorCode WriteSceneXdmf(MPI_Comm comm, const std::string &dir, const std::vector<PetscReal> &times, bool rigid, bool mesh) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank) PetscFunctionReturn(0);
  std::vector<std::string> r, m;
  if (rigid) r = UniformGrids(dir + "/rigid.xmf");
  if (mesh) m = UniformGrids(dir + "/mesh.xmf");
  FILE *fp = std::fopen((dir + "/scene.xmf").c_str(), "w");
  PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write %s/scene.xmf", dir.c_str());
  std::fprintf(fp, "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"2.0\">\n  <Domain>\n    <Grid Name=\"scene\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
  for (size_t i = 0; i < times.size(); ++i) {
    std::fprintf(fp, "    <Grid Name=\"frame_%zu\" GridType=\"Collection\" CollectionType=\"Spatial\">\n      <Time Value=\"%.17g\"/>\n", i, (double)times[i]);
    if (i < r.size()) std::fprintf(fp, "%s\n", r[i].c_str());
    if (i < m.size()) std::fprintf(fp, "%s\n", m[i].c_str());
    std::fprintf(fp, "    </Grid>\n");
  }
  std::fprintf(fp, "    </Grid>\n  </Domain>\n</Xdmf>\n");
  PetscCheck(std::fclose(fp) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "error writing %s/scene.xmf", dir.c_str());
  PetscFunctionReturn(0);
}

PetscErrorCode WriteBalanceRow(FILE *fp, const Balance &b) {
  PetscFunctionBeginUser;
  if (fp) {
    std::fprintf(fp, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", b.t, b.kinetic, b.strain, b.contact, b.gravity, b.fracture, b.external_work, b.dissipated, b.total, b.P[0], b.P[1], b.P[2], b.L[0], b.L[1], b.L[2]);
    std::fflush(fp);
  }
  PetscFunctionReturn(0);
}

// Time in the events that matter, summed over the main stage (rank 0's view, max over ranks).
PetscErrorCode PrintTimeSummary(MPI_Comm comm, double wall) {
  const char *events[] = {"TSStep", "FDEMSceneRHS", "FDEMSceneSearch", "FDEMSceneContact", "FDEMSceneHalo", "FDEMContactDetect", "FDEMContactForce", "FDEMContactHalo", "FDEMDContDetect", "FDEMDContForce", "FDEMDContGather"};
  PetscFunctionBeginUser;
  PetscCall(PetscPrintf(comm, "where the time went (max over ranks, inclusive):"));
  for (const char *name : events) {
    PetscLogEvent      ev = -1;
    PetscEventPerfInfo info;
    PetscCall(PetscLogEventGetId(name, &ev));
    if (ev < 0) continue;
    PetscCall(PetscLogEventGetPerfInfo(0, ev, &info));
    double tl = info.time, tg;
    PetscCallMPI(MPI_Allreduce(&tl, &tg, 1, MPI_DOUBLE, MPI_MAX, comm));
    if (info.count == 0 && tg == 0) continue;
    // (a share of the stepping's wall time; an event that also ran in the set-up can exceed a short run's)
    if (wall > 0 && tg <= wall) PetscCall(PetscPrintf(comm, " %s %.2f s (%.0f%%);", name, tg, 100 * tg / wall));
    else PetscCall(PetscPrintf(comm, " %s %.2f s;", name, tg));
  }
  PetscCall(PetscPrintf(comm, "\n"));
  PetscFunctionReturn(0);
}

// CPU time of this process (all its threads), s.
double CpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

// One line per contact object: searches, and the candidate and touching tetrahedron pairs of the
// last search and evaluation, in total and per body (what the broad phase hands the narrow phase).
PetscErrorCode PrintContactSummary(const Sim &s, PetscInt nbodies) {
  struct Item {
    const char      *what;
    FDEMContactStats st;
    bool             on;
  } items[3] = {{"rigid-rigid", {}, s.rc != nullptr}, {"deformable-deformable", {}, s.dc != nullptr}, {"combined", {}, s.sc != nullptr}};
  PetscFunctionBeginUser;
  if (s.rc) PetscCall(FDEMContactGetStats(s.rc, &items[0].st));
  if (s.dc) PetscCall(FDEMDeformableContactGetStats(s.dc, &items[1].st));
  if (s.sc) PetscCall(FDEMSceneGetContactStats(s.sc, &items[2].st));
  for (const Item &it : items) {
    if (!it.on || it.st.evaluations == 0) continue;
    const double per = nbodies > 0 ? 1.0 / (double)nbodies : 0;
    PetscCall(PetscPrintf(s.comm, "contact (%s): %" PetscInt_FMT " searches in %" PetscInt_FMT " evaluations; %" PetscInt_FMT " contact tetrahedra, %" PetscInt_FMT " ghosts; last search %" PetscInt_FMT " candidate pairs (%.1f per body), last evaluation %" PetscInt_FMT " touching (%.1f per body)\n", it.what, it.st.searches, it.st.evaluations,
                          it.st.primitives, it.st.ghosts, it.st.candidate_pairs, it.st.candidate_pairs * per, it.st.active_pairs, it.st.active_pairs * per));
    if (it.st.kept > 0)
      PetscCall(PetscPrintf(s.comm, "contact (%s): %" PetscInt_FMT " listings where joints broke or softened kept the last search (the same contact tetrahedra), %" PetscInt_FMT " of them made in place, %" PetscInt_FMT " of these asking again only the candidates of the records that changed\n", it.what, it.st.kept, it.st.in_place, it.st.in_place_few));
    if (it.st.onset != 0)
      PetscCall(PetscPrintf(s.comm, "contact (%s): faces that fracture exposed came into this run's contact with %.4g J of overlap energy, taken from balance.csv's fracture column (the handover to contact, doc/fracture.md)\n", it.what, (double)it.st.onset));
  }
  PetscFunctionReturn(0);
}

// dir/bodies.csv: the state of every rigid body at the end of the run (one row per body, in the
// order of the scene; R row by row), for comparing runs body by body.
PetscErrorCode WriteBodies(Sim &s, const std::string &file) {
  PetscInt            n;
  FDEMRigidBodyState *st = nullptr;
  PetscMPIInt         rank;
  FILE               *fp  = nullptr;
  int                 err = 0;
  PetscFunctionBeginUser;
  if (!s.rb) PetscFunctionReturn(0);
  if (s.U) PetscCall(SimRestore(s));
  PetscCallMPI(MPI_Comm_rank(s.comm, &rank));
  PetscCall(FDEMRigidGetBodyStates(s.rb, 0, &n, &st)); // on rank 0, in the order of the ids
  if (rank == 0) {
    fp = std::fopen(file.c_str(), "w");
    err = fp ? 0 : 1;
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, s.comm));
  if (err) PetscCall(PetscFree(st));
  PetscCheck(!err, s.comm, PETSC_ERR_FILE_OPEN, "cannot write %s", file.c_str());
  if (fp) std::fprintf(fp, "id,name,x,y,z,vx,vy,vz,wx,wy,wz,R00,R01,R02,R10,R11,R12,R20,R21,R22\n");
  for (PetscInt id = 0; fp && id < n; ++id) {
    const FDEMRigidBodyState &b = st[id];
    std::fprintf(fp, "%" PetscInt_FMT ",%s", id, RigidBodyName(s, id).c_str());
    for (const PetscReal *v : {b.x, b.v, b.omega_space})
      for (int k = 0; k < 3; ++k) std::fprintf(fp, ",%.17g", (double)v[k]);
    for (int k = 0; k < 9; ++k) std::fprintf(fp, ",%.17g", (double)b.R[k]);
    std::fprintf(fp, "\n");
  }
  PetscCall(PetscFree(st));
  if (fp) err = std::fclose(fp) != 0;
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, s.comm));
  PetscCheck(!err, s.comm, PETSC_ERR_FILE_WRITE, "error writing %s", file.c_str());
  PetscFunctionReturn(0);
}

// The fragments of the deformable bodies (FDEMDeformableGetLocalFragments; a body without a
// crack through it is one): with fracturable bodies prints their number; when file is not
// empty, writes one row per fragment, ordered by body and id, from rank 0, which gathers the
// ranks' shares for that. Collective.
PetscErrorCode WriteFragments(Sim &s, const std::string &file) {
  PetscInt      n;
  FDEMFragment *f;
  PetscMPIInt   rank, size;
  FILE         *fp  = nullptr;
  int           err = 0;
  PetscFunctionBeginUser;
  if (!s.dfm || (s.njoints == 0 && file.empty())) PetscFunctionReturn(0);
  if (s.U) PetscCall(SimRestore(s));
  PetscCallMPI(MPI_Comm_rank(s.comm, &rank));
  PetscCallMPI(MPI_Comm_size(s.comm, &size));
  PetscCall(FDEMDeformableGetLocalFragments(s.dfm, nullptr, &n, &f));
  // rank 0 gathers the shares (as bytes: the struct is PetscInt and PetscReal only)
  std::vector<FDEMFragment> all;
  std::vector<PetscMPIInt>  cnt(size), off(size + 1, 0);
  const PetscMPIInt         bytes = (PetscMPIInt)(n * sizeof(FDEMFragment));
  PetscCallMPI(MPI_Gather(&bytes, 1, MPI_INT, cnt.data(), 1, MPI_INT, 0, s.comm));
  long long sum = 0;
  for (PetscMPIInt r = 0; r < size; ++r) sum += cnt[r];
  if (rank == 0 && sum > INT_MAX) err = 1;
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, s.comm));
  if (err) PetscCall(PetscFree(f));
  PetscCheck(!err, s.comm, PETSC_ERR_SUP, "%s: too many fragments to write from one rank", file.c_str());
  for (PetscMPIInt r = 0; r < size; ++r) off[r + 1] = off[r] + cnt[r];
  if (rank == 0) all.resize(off[size] / sizeof(FDEMFragment));
  PetscCallMPI(MPI_Gatherv(f, bytes, MPI_BYTE, all.data(), cnt.data(), off.data(), MPI_BYTE, 0, s.comm));
  PetscCall(PetscFree(f));
  std::sort(all.begin(), all.end(), [](const FDEMFragment &a, const FDEMFragment &b) { return a.body != b.body ? a.body < b.body : a.id < b.id; });
  PetscInt total = 0;
  PetscCallMPI(MPI_Allreduce(&n, &total, 1, MPIU_INT, MPI_SUM, s.comm));
  if (s.njoints > 0) PetscCall(PetscPrintf(s.comm, "fragments: %" PetscInt_FMT " (connected pieces of the deformable bodies over their unbroken joints)%s%s\n", total, file.empty() ? "" : "; ", file.c_str()));
  if (!file.empty() && rank == 0) {
    fp  = std::fopen(file.c_str(), "w");
    err = fp ? 0 : 1;
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, s.comm));
  PetscCheck(!err, s.comm, PETSC_ERR_FILE_OPEN, "cannot write %s", file.c_str());
  if (fp) {
    std::fprintf(fp, "fragment,body,mass,x,y,z,vx,vy,vz,first_element,elements\n");
    for (std::size_t i = 0; i < all.size(); ++i) {
      const char *name;
      PetscCall(FDEMDeformableGetBodyName(s.dfm, all[i].body, nullptr, &name));
      std::fprintf(fp, "%zu,%s,%.17g", i, name, (double)all[i].mass);
      for (const PetscReal *v : {all[i].x, all[i].v})
        for (int k = 0; k < 3; ++k) std::fprintf(fp, ",%.17g", (double)v[k]);
      std::fprintf(fp, ",%" PetscInt_FMT ",%" PetscInt_FMT "\n", all[i].id, all[i].cells);
    }
    err = std::fclose(fp) != 0;
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, s.comm));
  PetscCheck(!err, s.comm, PETSC_ERR_FILE_WRITE, "error writing %s", file.c_str());
  PetscFunctionReturn(0);
}

// The joints that broke since the last call (FDEMDeformableGetJointBreaks), one row each in
// fracture.csv (fp, rank 0): the time, the step in which it broke (the first step ending at
// or after that time), the joint, its body and its centroid. Collective.
PetscErrorCode WriteJointBreaks(Sim &s, FILE *fp, PetscReal dt) {
  PetscInt        n;
  FDEMJointBreak *e;
  PetscFunctionBeginUser;
  if (!s.dfm || s.njoints == 0) PetscFunctionReturn(0);
  PetscCall(FDEMDeformableGetJointBreaks(s.dfm, &n, &e));
  for (PetscInt i = 0; fp && i < n; ++i) {
    const char *name;
    PetscCall(FDEMDeformableGetBodyName(s.dfm, e[i].body, nullptr, &name));
    std::fprintf(fp, "%.17g,%lld,%" PetscInt_FMT ",%s,%.17g,%.17g,%.17g\n", (double)e[i].t, (long long)std::ceil(e[i].t / dt - 1e-6), e[i].joint, name, (double)e[i].x[0], (double)e[i].x[1], (double)e[i].x[2]);
  }
  if (fp && n) std::fflush(fp);
  PetscCall(PetscFree(e));
  PetscFunctionReturn(0);
}

PetscErrorCode MakeDir(MPI_Comm comm, const std::string &dir) {
  PetscMPIInt rank;
  int         err = 0;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    std::string path;
    for (size_t i = 0; i <= dir.size(); ++i) {
      if (i == dir.size() || dir[i] == '/') {
        if (!path.empty() && mkdir(path.c_str(), 0777) != 0 && errno != EEXIST) err = 1;
      }
      if (i < dir.size()) path += dir[i];
    }
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_OPEN, "cannot create the output folder %s", dir.c_str());
  PetscFunctionReturn(0);
}

// The TS options of every segment: the scene's step and end, then the options database (the command line wins).
PetscErrorCode ConfigureTS(Sim &s, PetscReal dt, PetscReal end) {
  PetscFunctionBeginUser;
  PetscCall(TSSetTimeStep(s.ts, dt));
  PetscCall(TSSetMaxTime(s.ts, end));
  PetscCall(TSSetExactFinalTime(s.ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSSetFromOptions(s.ts));
  PetscFunctionReturn(0);
}

// The temporary name of DIR/checkpoint.h5: checkpoint.h5.tmp-<hash of DIR's real path>.
// Unique per folder, because Open MPI's MPI-IO names a semaphore after the file's base
// name only: two runs writing "checkpoint.h5.tmp" in two folders at once blocked each
// other. The same on every rank (rank 0's path) and from run to run in one folder.
static PetscErrorCode TemporaryName(MPI_Comm comm, const std::string &dir, const std::string &ck, std::string &tmp) {
  PetscMPIInt        rank;
  unsigned long long h = 0;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    char *real = realpath(dir.c_str(), nullptr);
    h          = std::hash<std::string>{}(real ? std::string(real) : dir);
    free(real);
  }
  PetscCallMPI(MPI_Bcast(&h, 1, MPI_UNSIGNED_LONG_LONG, 0, comm));
  char hex[32];
  std::snprintf(hex, sizeof hex, "%016llx", h);
  tmp = ck + ".tmp-" + hex;
  PetscFunctionReturn(0);
}

// Writes DIR/checkpoint.h5 atomically: the file is written under a temporary name
// (TemporaryName) and renamed over the previous one, which is first kept as
// checkpoint.1.h5 (a hard link, so that a checkpoint.h5 exists at every moment); older
// ones shift to .2, .3, ... up to `keep` files.
PetscErrorCode WriteCheckpoint(Sim &s, const std::string &dir, long keep, PetscReal t, PetscInt step, PetscReal dt, bool kill) {
  PetscMPIInt       rank;
  const std::string ck = dir + "/checkpoint.h5";
  std::string       tmp;
  int               err = 0;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(s.comm, &rank));
  PetscCall(TemporaryName(s.comm, dir, ck, tmp));
  PetscCall(SimWriteCheckpoint(s, tmp.c_str(), t, step, dt));
  PetscCallMPI(MPI_Barrier(s.comm));
  if (kill) raise(SIGKILL);
  if (rank == 0) {
    auto name = [&](long k) { return dir + "/checkpoint." + std::to_string(k) + ".h5"; };
    for (long k = keep - 1; k >= 2; --k) std::rename(name(k - 1).c_str(), name(k).c_str());
    if (keep >= 2 && access(ck.c_str(), F_OK) == 0) {
      unlink(name(1).c_str());
      if (link(ck.c_str(), name(1).c_str()) != 0) err = 1;
    }
    if (std::rename(tmp.c_str(), ck.c_str()) != 0) err = 1;
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, s.comm));
  PetscCheck(!err, s.comm, PETSC_ERR_FILE_WRITE, "cannot rename the checkpoint %s into %s", tmp.c_str(), ck.c_str());
  PetscFunctionReturn(0);
}

// -restart FILE: a file that rank 0 can read and that holds HDF5's signature (at byte 0, 512,
// 1024, 2048, ...), so that a wrong path is named as such rather than by HDF5's own failure.
PetscErrorCode CheckRestartFile(MPI_Comm comm, const char *path) {
  PetscMPIInt rank;
  char        why[256] = "";
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    struct stat st;
    FILE       *f = nullptr;
    if (stat(path, &st) != 0) std::snprintf(why, sizeof why, "%s", std::strerror(errno));
    else if (!S_ISREG(st.st_mode)) std::snprintf(why, sizeof why, "not a file");
    else if (!(f = std::fopen(path, "rb"))) std::snprintf(why, sizeof why, "%s", std::strerror(errno));
    else {
      static const unsigned char sig[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
      bool                       found  = false;
      for (long long off = 0; !found && off + 8 <= (long long)st.st_size; off = off ? 2 * off : 512) {
        unsigned char b[8];
        found = std::fseek(f, (long)off, SEEK_SET) == 0 && std::fread(b, 1, 8, f) == 8 && std::memcmp(b, sig, 8) == 0;
      }
      std::fclose(f);
      if (!found) std::snprintf(why, sizeof why, "not an HDF5 file");
    }
  }
  PetscCallMPI(MPI_Bcast(why, sizeof why, MPI_CHAR, 0, comm));
  PetscCheck(!why[0], comm, PETSC_ERR_FILE_OPEN, "-restart %s: %s (give the checkpoint.h5 that a run of this scene wrote)", path, why);
  PetscFunctionReturn(0);
}

// PETSc reads an integer option with strtoll and keeps the low bits (-ts_max_steps 4294967297 is
// 1 step): the integer options of a run, checked against this build's range before they are read.
PetscErrorCode CheckIntegerOptions(MPI_Comm comm) {
  PetscFunctionBeginUser;
  for (const char *name : {"-ts_max_steps", "-fdem_insert_every", "-fdem_checkpoint_kill", "-ts_fdem_check_interval", "-ts_max_reject", "-ts_max_snes_failures", "-ts_monitor_frequency"}) {
    char      v[256];
    PetscBool set;
    PetscCall(PetscOptionsGetString(nullptr, nullptr, name, v, sizeof v, &set));
    if (!set) continue;
    char *end = nullptr;
    errno     = 0;
    const long long n = std::strtoll(v, &end, 10);
    const bool integer = end != v && *end == '\0'; // (PETSc's own parse names other strings)
    PetscCheck(!integer || (errno != ERANGE && n >= PETSC_MIN_INT && n <= PETSC_MAX_INT), comm, PETSC_ERR_USER_INPUT, "%s %s: beyond the integers this build counts (%" PetscInt_FMT " at most)", name, v, (PetscInt)PETSC_MAX_INT);
  }
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode RunOptionsFromCommandLine(MPI_Comm comm, RunOptions &o) {
  PetscFunctionBeginUser;
  PetscCall(CheckIntegerOptions(comm));
  PetscOptionsBegin(comm, nullptr, "fdem driver (scene keys: fdem --help)", "fdem");
  PetscCall(PetscOptionsString("-fdem_output", "output folder (overrides output.dir of the scene; none: write nothing)", "", o.output, o.output, sizeof(o.output), nullptr));
  PetscCall(PetscOptionsBool("-fdem_progress", "progress line on rank 0 (at most once per second)", "", o.progress, &o.progress, nullptr));
  PetscCall(PetscOptionsReal("-fdem_balance_gain_limit", "stop when balance.csv shows the scene gained more than this fraction of its energy (an unstable step); 0: never", "", o.gain_limit, &o.gain_limit, nullptr));
  PetscCall(PetscOptionsInt("-fdem_insert_every", "steps between the searches for tetrahedra that get joints during the run (materials' fracture.insert_at)", "", o.insert_every, &o.insert_every, nullptr));
  PetscCall(PetscOptionsReal("-fdem_insert_heap", "room kept in the heap for the rebuilds of a run that inserts joints, times the memory in use after the set-up, on transparent huge pages where the system offers them (0: none)", "", o.insert_heap, &o.insert_heap, nullptr));
  PetscCall(PetscOptionsString("-restart", "continue the scene from this checkpoint (e.g. out/checkpoint.h5)", "", o.restart, o.restart, sizeof(o.restart), nullptr));
  PetscCall(PetscOptionsInt("-fdem_checkpoint_kill", "(tests) kill the process with SIGKILL after writing the k-th checkpoint's temporary file, before the rename", "", o.kill_in_checkpoint, &o.kill_in_checkpoint, nullptr));
  PetscOptionsEnd();
  PetscCheck(o.gain_limit >= 0, comm, PETSC_ERR_USER_INPUT, "-fdem_balance_gain_limit %g: give a fraction >= 0 (0: never stop)", (double)o.gain_limit);
  PetscCheck(o.insert_heap >= 0 && o.insert_heap <= 100, comm, PETSC_ERR_USER_INPUT, "-fdem_insert_heap %.4g: give a factor from 0 (none) to 100", (double)o.insert_heap);
  PetscCheck(o.insert_every >= 1, comm, PETSC_ERR_USER_INPUT, "-fdem_insert_every %" PetscInt_FMT ": give a number of steps >= 1", o.insert_every);
  PetscFunctionReturn(0);
}

PetscErrorCode RunScene(MPI_Comm comm, const Scene &sc, std::vector<kernels::TetMesh> meshes, const RunOptions &o) {
  Sim            s;
  PetscMPIInt    rank, size;
  PetscLogDouble w0, w1, wbuild;
  char           scheme[64];
  PetscBool      flg;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscTime(&w0));
  PetscCall(PetscStrncpy(scheme, sc.scheme.c_str(), sizeof(scheme)));
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-ts_type", scheme, sizeof(scheme), &flg)); // the TS's own option (TSSetFromOptions lists it)
  // the TS would take -ts_init_time at every set-up (also after each rebuild and checkpoint), while
  // the steps, the output intervals and the moved bodies count from the run's own start
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-ts_init_time", &flg));
  PetscCheck(!flg, comm, PETSC_ERR_USER_INPUT, "-ts_init_time: a run starts at t = 0, or at its checkpoint's time with -restart; leave it out (-ts_max_time or time.end sets the end)");
  if (o.restart[0]) { // a checkpoint's overlaps were made by the run: a deep one is a warning, unless the command line says otherwise
    PetscBool given;
    PetscCall(PetscOptionsHasName(nullptr, nullptr, "-fdem_contact_initial_overlap_check", &given));
    if (!given) PetscCall(PetscOptionsSetValue(nullptr, "-fdem_contact_initial_overlap_check", "false"));
  }
  std::vector<PetscInt> split_cells; // the tetrahedra a checkpoint's run had split by insertion
  if (o.restart[0]) {
    PetscCall(CheckRestartFile(comm, o.restart));
    PetscCall(SimReadFractureCells(comm, o.restart, split_cells));
  }
  if (!split_cells.empty()) {
    bool inserting = false;
    for (const Body &b : sc.bodies) {
      const Material *m = b.material.empty() ? nullptr : sc.FindMaterial(b.material);
      inserting         = inserting || (b.model == "deformable" && m && m->fracture.present && m->fracture.insert_at > 0);
    }
    PetscCheck(inserting, comm, PETSC_ERR_USER_INPUT, "%s: the checkpoint %s was written by a run that inserted joints during the run (at %zu tetrahedra), but no deformable body of this scene has a material with fracture.insert_at: restart with the scene it was written with", sc.file.c_str(), o.restart, split_cells.size());
  }
  PetscCall(SimBuild(comm, sc, std::move(meshes), s, split_cells));
  PetscReal t = 0, dt_restart = 0;
  PetscInt  step = 0;
  if (o.restart[0]) {
    PetscCall(SimReadCheckpoint(s, o.restart, &t, &step, &dt_restart));
    // the partition a straight run has after the checkpoint (it migrates there, to slabs balanced on the bodies' places)
    if (SimNeedsMigration(s)) PetscCall(SimMigrate(s));
    PetscCall(PetscPrintf(comm, "restart from %s: t = %.6g s, step %" PetscInt_FMT "\n", o.restart, (double)t, step));
  }
  PetscCall(SimSetUpTS(s, scheme, t, step));
  StableStep st;
  PetscCall(SimStableStep(s, scheme, sc.safety, st));
  PetscReal dt = dt_restart > 0 ? dt_restart : sc.dt > 0 ? sc.dt : st.dt, end = sc.end;
  const PetscReal dt_chosen = dt;
  PetscCall(ConfigureTS(s, dt, end));
  PetscCall(TSGetTimeStep(s.ts, &dt));
  const char *dt_from = dt != dt_chosen ? "-ts_dt" : dt_restart > 0 ? "from the checkpoint" : sc.dt > 0 ? "from the scene" : "auto"; // the command line wins
  PetscCall(TSGetMaxTime(s.ts, &end));
  // -ts_dt and -ts_max_time of the command line come through TSSetFromOptions unchecked
  // (an option's message is placed by the caller: the command line, or the scene's petsc:)
  const bool dt_option = dt != dt_chosen, end_option = end != sc.end;
  PetscCheck(dt > 0 && std::isfinite(dt), comm, PETSC_ERR_USER_INPUT, "%s%sthe time step %g s (%s) must be positive and finite", dt_option ? "" : sc.time_where.c_str(), dt_option ? "" : ": ", (double)dt, dt_from);
  PetscCheck(std::isfinite(end) && (end > t || (o.restart[0] && end == t)), comm, PETSC_ERR_USER_INPUT, "%s%sthe run's end t = %g s (%s) must be finite and after its start, t = %g s%s", end_option ? "" : sc.time_where.c_str(), end_option ? "" : ": ", (double)end,
             end_option ? "-ts_max_time" : "time.end", (double)t, o.restart[0] ? " (the checkpoint's time)" : "");
  PetscCall(PetscTime(&wbuild));
  const PetscInt nbodies = (PetscInt)sc.bodies.size();
  PetscCall(PetscPrintf(comm, "%s%s%s: %d bodies (%d rigid, %d deformable), %" PetscInt_FMT " tetrahedra, %" PetscInt_FMT " nodes (%" PetscInt_FMT " fixed, %" PetscInt_FMT " moved), %" PetscInt_FMT " degrees of freedom, %d ranks\n", sc.file.c_str(),
                        sc.title.empty() ? "" : " -- ", sc.title.c_str(), (int)nbodies, (int)s.rigid_bodies.size(), (int)s.deformable_bodies.size(), s.ntets, s.nnodes, s.nfixed_nodes, s.nmoved_nodes, s.ndofs, (int)size));
  if (s.njoints > 0) {
    std::string zoned; // the bodies split in their fracture zones only
    int         nzoned = 0;
    for (int i : s.deformable_bodies)
      if (!sc.bodies[i].fracture_zones.empty() && nzoned++ < 3) zoned += (zoned.empty() ? "'" : ", '") + sc.bodies[i].name + "'";
    if (nzoned > 3) zoned += " and " + std::to_string(nzoned - 3) + " more";
    if (nzoned) zoned = "; " + zoned + (nzoned > 1 ? ": only those in their fracture_zone" : ": only those in its fracture_zone");
    PetscCall(PetscPrintf(comm, "fracture: %" PetscInt_FMT " joints (the fracturable bodies' tetrahedra have nodes of their own%s; %" PetscInt_FMT " nodes after the split); balance.csv: strain includes the joints' stored energy, fracture is the energy their damage dissipated and their handover to contact took out\n", s.njoints, zoned.c_str(), s.nnodes));
  }
  if (s.inserting)
    PetscCall(PetscPrintf(comm, "fracture: joints inserted during the run: every %" PetscInt_FMT " steps (-fdem_insert_every), the whole tetrahedra of bodies of a material with fracture.insert_at whose stress has reached that fraction of the strength get nodes of their own and joints, with their neighbours; %" PetscInt_FMT " split so far\n", o.insert_every, (PetscInt)split_cells.size()));
  const double wmax = std::max({st.omega_elements, st.omega_contact, st.omega_joints});
  char         wj[64] = "";
  if (s.njoints > 0) std::snprintf(wj, sizeof wj, ", joints %.4g /s", st.omega_joints);
  PetscCall(PetscPrintf(comm, "time step %.4g s (%s; stable limit K_crit/omega_max = %.4g s for -ts_type %s, K_crit = %.6g, omega elements %.4g /s, contact %.4g /s%s; limited by %s); end %.4g s\n", (double)dt, dt_from,
                        wmax > 0 ? st.kcrit / wmax : 0.0, scheme, st.kcrit, st.omega_elements, st.omega_contact, wj, st.limit.c_str(), (double)end));
  // a step beyond the stable limit, given (the scene, -ts_dt or the checkpoint): an explicit
  // scheme's error then grows without bound, which the balance check below stops once it shows
  if (wmax > 0 && dt * wmax > st.kcrit * (1 + 1e-12)) {
    const std::string from = dt != dt_chosen ? std::string("-ts_dt") : dt_restart > 0 ? std::string("the checkpoint ") + o.restart : sc.dt_where + ": time.dt";
    PetscCall(PetscPrintf(comm, "WARNING %s: the time step %.4g s is %.3g times the stable limit K_crit/omega_max = %.4g s of -ts_type %s (limited by %s): beyond it the scheme is unstable wherever that frequency is reached (a run that gains energy stops, -fdem_balance_gain_limit); lower the step, or give time.dt: auto (the limit times time.safety)\n", from.c_str(), (double)dt,
                          (double)(dt * wmax / st.kcrit), st.kcrit / wmax, scheme, st.limit.c_str()));
  }
  const double steps_to_end = std::ceil(end / dt * (1 - 1e-12));
  PetscInt     max_steps;
  PetscBool    max_steps_set;
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-ts_max_steps", &max_steps, &max_steps_set)); // the command line wins: the run stops at that step
  PetscCheck(!max_steps_set || max_steps >= 0, comm, PETSC_ERR_USER_INPUT, "-ts_max_steps %" PetscInt_FMT ": give the step number to stop at, 0 or more", max_steps);
  const bool capped = max_steps_set && (double)max_steps < steps_to_end; // (then the steps to the end need not be counted)
  PetscCheck(capped || steps_to_end < 0.5 * PETSC_MAX_INT, comm, PETSC_ERR_USER_INPUT, "%s: the run to t = %g s in steps of %g s (%s) takes %.3g steps, more than this build counts (%d): shorten time.end or lengthen the step", sc.time_where.c_str(), (double)end, (double)dt,
             dt_from, steps_to_end, (int)(PETSC_MAX_INT / 2));
  // (-ts_max_steps 0, or a step at or before a restart's: the state is set up and written, no step made)
  const PetscInt nsteps = capped ? max_steps : std::max<PetscInt>(1, (PetscInt)steps_to_end);
  // the steps in an output interval (at least one, at most the run: an interval beyond the end
  // means "at the end", and the count never leaves the range of PetscInt)
  auto steps_in = [&](double interval) { return (PetscInt)std::clamp(std::round(interval / dt), 1.0, (double)std::max<PetscInt>(nsteps, 1)); };
  if (o.check_only) {
    // time a few steps on a copy of the state
    Vec            U0;
    PetscLogDouble t0, t1;
    PetscLogDouble mem;
    const PetscInt probe = 3;
    PetscCall(VecDuplicate(s.U, &U0));
    PetscCall(VecCopy(s.U, U0));
    PetscCall(TSSetMaxSteps(s.ts, 1));
    PetscCall(TSSolve(s.ts, s.U));
    PetscCall(PetscTime(&t0));
    PetscCall(TSSetMaxSteps(s.ts, 1 + probe));
    PetscCall(TSSolve(s.ts, s.U));
    PetscCall(PetscTime(&t1));
    PetscCall(VecCopy(U0, s.U));
    PetscCall(VecDestroy(&U0));
    PetscCall(PetscMemoryGetCurrentUsage(&mem));
    PetscLogDouble memg;
    PetscCallMPI(MPI_Allreduce(&mem, &memg, 1, MPI_DOUBLE, MPI_SUM, comm));
    const double per = (t1 - t0) / probe;
    PetscCall(PetscPrintf(comm, "check: %" PetscInt_FMT " steps to the end; measured %.3g s per step (%d steps after one warm-up) -> about %.3g s for the run; memory in use %.1f MB (all ranks, resident)\n", nsteps, per, (int)probe, per * nsteps, memg / 1048576.0));
    PetscCall(PetscPrintf(comm, "check: the scene is valid\n"));
    PetscCall(SimDestroy(s));
    PetscFunctionReturn(0);
  }

  // output
  const std::string dir   = o.output[0] ? std::string(o.output) : sc.output_dir;
  const bool        write = dir != "none";
  // a restarted run appends to balance.csv and writes its frames into DIR/restart_<step>
  const std::string fdir  = o.restart[0] ? dir + "/restart_" + std::to_string((long long)step) : dir;
  FILE             *bal   = nullptr, *loads = nullptr, *breaks = nullptr;
  if (write) {
    PetscCall(MakeDir(comm, fdir));
    if (rank == 0) {
      const std::string file = dir + "/balance.csv";
      const bool        head = !o.restart[0] || access(file.c_str(), F_OK) != 0;
      bal                    = std::fopen(file.c_str(), o.restart[0] ? "a" : "w");
      PetscCheck(bal, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write %s/balance.csv", dir.c_str());
      if (head) std::fprintf(bal, "time,kinetic,strain,contact,gravity,fracture,external_work,dissipated,total,px,py,pz,Lx,Ly,Lz\n");
    }
  }
  // the moved rigid bodies (platens): their loads in loads.csv, a row with each balance row
  std::vector<std::pair<PetscInt, std::string>> platens; // rigid id, name
  for (size_t k = 0; k < s.rigid_bodies.size(); ++k)
    if (sc.bodies[s.rigid_bodies[k]].moved) platens.push_back({(PetscInt)k, sc.bodies[s.rigid_bodies[k]].name});
  if (write && !platens.empty() && rank == 0) {
    const std::string file = dir + "/loads.csv";
    const bool        head = !o.restart[0] || access(file.c_str(), F_OK) != 0;
    loads                  = std::fopen(file.c_str(), o.restart[0] ? "a" : "w");
    PetscCheck(loads, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write %s/loads.csv", dir.c_str());
    if (head) {
      std::fprintf(loads, "time");
      for (const auto &p : platens) std::fprintf(loads, ",%s_Fx,%s_Fy,%s_Fz", p.second.c_str(), p.second.c_str(), p.second.c_str());
      std::fprintf(loads, "\n");
    }
  }
  // the joints' breaks, one row each as they happen, in fracture.csv
  if (write && (s.njoints > 0 || s.inserting) && rank == 0) {
    const std::string file = dir + "/fracture.csv";
    const bool        head = !o.restart[0] || access(file.c_str(), F_OK) != 0;
    breaks                 = std::fopen(file.c_str(), o.restart[0] ? "a" : "w");
    PetscCheck(breaks, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write %s/fracture.csv", dir.c_str());
    if (head) std::fprintf(breaks, "time,step,joint,body,x,y,z\n");
  }
  // segments end at balance rows; frames every `fevery` steps (a multiple of the segment)
  const PetscInt fsteps = sc.output_every > 0 ? steps_in(sc.output_every) : std::max<PetscInt>(1, nsteps / 50);
  const PetscInt every  = sc.output_balance > 0 ? steps_in(sc.output_balance) : std::max<PetscInt>(1, fsteps / 10);
  const PetscInt fevery = std::max<PetscInt>(1, fsteps / every) * every;
  const PetscInt csteps = sc.checkpoint_every > 0 ? (PetscInt)std::clamp(std::round(sc.checkpoint_every / dt / every), 1.0, (double)(nsteps / every + 1)) * every : 0;
  std::vector<PetscReal> frames;
  Balance                b;
  b.t = t;
  if (s.rc && !o.restart[0]) { // bodies that touch at the start: the first row's contact energy
    FDEMContactStats st;
    PetscReal        e;
    PetscCall(FDEMContactGetStats(s.rc, &st));
    if (st.evaluations == 0) PetscCall(FDEMContactComputeEnergy(s.rc, &e));
  }
  PetscCall(SimBalance(s, b));
  const Balance first = b;
  if (!o.restart[0]) PetscCall(WriteBalanceRow(bal, b));
  // The energy-gain stop's reference: this first balance, unless the rigid contact has not been
  // evaluated yet (at a restart), whose energy it then lacks, so that the first segment would
  // seem to gain the contact energy: then the first row after it
  Balance gain_ref = first;
  bool    gain_ref_set = true;
  if (s.rc) {
    FDEMContactStats st;
    PetscCall(FDEMContactGetStats(s.rc, &st));
    gain_ref_set = st.evaluations > 0;
  }
  if (write) {
    PetscCall(SimWriteOutput(s, fdir, step, t));
    frames.push_back(t);
  }
  Progress prog;
  prog.end    = end;
  prog.bodies = nbodies;
  prog.on     = o.progress;
  prog.rank   = rank;
  prog.tty    = isatty(fileno(stdout)) ? PETSC_TRUE : PETSC_FALSE;
  prog.step0  = step;
  const double cpu0 = CpuSeconds();
  PetscCall(PetscTime(&prog.wall0));
  prog.last = prog.wall0;
  PetscCall(TSMonitorSet(s.ts, ProgressMonitor, &prog, nullptr));
  double   maxdP        = 0, scale = 0;
  PetscInt ncheckpoints = 0;
  // with joints inserted during the run, segments also end every o.insert_every steps
  const PetscInt ins = s.inserting ? o.insert_every : 0;
  PetscInt       ninserted = 0, ninsertions = 0;
  PetscLogDouble insert_time = 0; // wall time of the searches and rebuilds
  if (ins) ReserveHeapForRebuilds(o.insert_heap);
  while (step < nsteps && t < end * (1 - 1e-12)) {
    TSConvergedReason reason;
    PetscInt          next = (step / every + 1) * every;
    if (ins) next = std::min(next, (step / ins + 1) * ins);
    PetscCall(TSSetMaxSteps(s.ts, std::min(nsteps, next)));
    PetscCall(TSSolve(s.ts, s.U));
    PetscCall(TSGetConvergedReason(s.ts, &reason));
    PetscCall(TSGetTime(s.ts, &t));
    PetscCall(TSGetStepNumber(s.ts, &step));
    PetscCheck(reason >= 0, comm, PETSC_ERR_NOT_CONVERGED, "%s: the time stepping failed at t = %g, step %" PetscInt_FMT " (%s); try a smaller time.dt or time.safety", sc.file.c_str(), (double)t, step, TSConvergedReasons[reason]);
    const bool last = step >= nsteps || t >= end * (1 - 1e-12);
    if (ins && !last && step % ins == 0) { // joints where the stress nears the strength: the scene built again with them
      std::vector<PetscInt> cells;
      PetscLogDouble        i0, i1;
      PetscCall(PetscTime(&i0));
      PetscCall(SimRestore(s));
      PetscCall(SimFindCellsToSplit(s, cells));
      if (!cells.empty()) {
        if (write) PetscCall(WriteJointBreaks(s, breaks, dt)); // (this model's; the next numbers its joints anew)
        PetscCall(SimEndTS(s));
        PetscCall(SimInsertJoints(s, cells));
        if (SimNeedsMigration(s)) PetscCall(SimMigrate(s));
        PetscCall(SimSetUpTS(s, scheme, t, step));
        PetscCall(ConfigureTS(s, dt, end));
        PetscCall(TSMonitorSet(s.ts, ProgressMonitor, &prog, nullptr));
        ninserted += (PetscInt)cells.size();
        ++ninsertions;
        if (o.progress) PetscCall(PetscPrintf(comm, "%st = %.5g s: joints inserted at %zu tetrahedra whose stress neared the strength (%" PetscInt_FMT " joints, %" PetscInt_FMT " nodes now)\n", prog.tty ? "\r" : "", (double)t, cells.size(), s.njoints, s.nnodes));
      }
      PetscCall(PetscTime(&i1));
      insert_time += i1 - i0;
    }
    if (step % every != 0 && !last) continue; // (a segment that ended for the insertion only)
    b.t = t;
    PetscCall(SimBalance(s, b));
    for (int k = 0; k < 3; ++k) maxdP = std::max(maxdP, std::fabs(b.P[k] - first.P[k]));
    PetscCall(WriteBalanceRow(bal, b));
    if (write) PetscCall(WriteJointBreaks(s, breaks, dt));
    // an energy gain far above the integration error is an unstable step: stop, and say why
    scale = std::max(scale, b.kinetic + std::fabs(b.strain) + std::fabs(b.contact) + b.fracture + std::fabs(b.external_work) + std::fabs(b.gravity - first.gravity));
    // (above the round-off of the totals, which hold gravity's arbitrary datum, and above 1e-12 J,
    // the round-off of a scene at rest whose energies are all zero)
    if (!gain_ref_set) gain_ref = b, gain_ref_set = true;
    const PetscReal gain = -(b.dissipated - gain_ref.dissipated);
    if (o.gain_limit > 0 && gain > o.gain_limit * scale && gain > 1e-9 * (std::fabs(first.total) + std::fabs(first.gravity) + scale) && gain > 1e-12) {
      if (bal) std::fflush(bal);
      SETERRQ(comm, PETSC_ERR_NOT_CONVERGED,
              "%s: the scene gained %g J by t = %g s (step %" PetscInt_FMT "), %.3g%% of its energy (%g J: kinetic, stored, and the work of gravity and of the moved bodies), far more than the integration error: the time step is unstable for some contact or element. "
              "dt: auto bounds one contact of the stiffest kind; dense packs (a body pressed by several at once) and elongated bodies' rotation can be faster: lower time.safety or time.dt (-fdem_balance_gain_limit %g stops at this fraction; 0 never stops).",
              sc.dt_where.c_str(), (double)gain, (double)t, step, 100 * (double)(gain / scale), (double)scale, (double)o.gain_limit);
    }
    if (write && !platens.empty()) { // the force on each platen at the segment's last evaluation (collective)
      std::vector<PetscReal> F(3 * platens.size());
      for (size_t k = 0; k < platens.size(); ++k) PetscCall(FDEMRigidGetBodyForce(s.rb, platens[k].first, &F[3 * k]));
      if (loads) {
        std::fprintf(loads, "%.17g", (double)t);
        for (PetscReal f : F) std::fprintf(loads, ",%.17g", (double)f);
        std::fprintf(loads, "\n");
        std::fflush(loads);
      }
    }
    if (write && (step % fevery == 0 || last)) {
      PetscCall(SimWriteOutput(s, fdir, step, t));
      frames.push_back(t);
    }
    // at a checkpoint the TS ends (and a new one starts): a restarted run does the same steps
    const bool checkpoint = write && csteps > 0 && (step % csteps == 0 || last);
    if (checkpoint) {
      PetscCall(SimEndTS(s));
      ++ncheckpoints;
      PetscCall(WriteCheckpoint(s, dir, sc.checkpoint_keep, t, step, dt, ncheckpoints == o.kill_in_checkpoint));
      if (!last) {
        PetscCall(SimMigrate(s));
        PetscCall(SimSetUpTS(s, scheme, t, step));
        PetscCall(ConfigureTS(s, dt, end));
        PetscCall(TSMonitorSet(s.ts, ProgressMonitor, &prog, nullptr));
      }
    } else if (!last && SimNeedsMigration(s)) { // the TS goes on unless a rigid body has moved far enough
      PetscBool due;
      PetscCall(SimMigrationDue(s, &due)); // (SimBalance above copied the state into the models)
      if (due) {
        PetscCall(SimEndTS(s));
        PetscCall(SimMigrate(s));
        PetscCall(SimSetUpTS(s, scheme, t, step));
        PetscCall(ConfigureTS(s, dt, end));
        PetscCall(TSMonitorSet(s.ts, ProgressMonitor, &prog, nullptr));
      }
    }
  }
  PetscCall(PetscTime(&w1));
  const double cpu1 = CpuSeconds();
  if (prog.on && prog.tty && rank == 0) std::fprintf(stdout, "\n");
  if (bal) std::fclose(bal);
  if (loads) std::fclose(loads);
  if (breaks) std::fclose(breaks);
  if (write) PetscCall(WriteSceneXdmf(comm, fdir, frames, s.rb != nullptr, s.dfm != nullptr));
  if (write) PetscCall(WriteBodies(s, fdir + "/bodies.csv"));
  const double run = w1 - prog.wall0;
  double cpu = cpu1 - cpu0, maxcpu; // the busiest rank's CPU time in the stepping (a loaded machine slows the wall clock)
  PetscCallMPI(MPI_Allreduce(&cpu, &maxcpu, 1, MPI_DOUBLE, MPI_MAX, comm));
  const PetscInt ran = step - prog.step0; // steps of this run (a restart starts at the checkpoint's)
  PetscCall(PetscPrintf(comm, "done: t = %.6g s in %" PetscInt_FMT " steps (to step %" PetscInt_FMT "); wall time %.2f s (set-up %.2f s, stepping %.3f s: %.1f steps/s, %.3g body-steps/s; stepping CPU time %.3f s on the busiest rank: %.3g body-steps/s/core)\n", (double)t, ran, step,
                        w1 - w0, wbuild - w0, run, run > 0 ? ran / run : 0.0, run > 0 ? ran * (double)nbodies / run : 0.0, maxcpu, maxcpu > 0 ? ran * (double)nbodies / (maxcpu * size) : 0.0));
  PetscCall(PetscPrintf(comm, "balance: energy at start %.6g J, at end %.6g J (kinetic %.4g, strain %.4g, contact %.4g, gravity %.4g, fracture %.4g), dissipated %.4g J; momentum change max %.3g kg m/s\n", first.total, b.total, b.kinetic, b.strain, b.contact, b.gravity,
                        b.fracture, b.dissipated, maxdP));
  if (s.inserting) PetscCall(PetscPrintf(comm, "fracture: joints inserted %" PetscInt_FMT " times in this run, at %" PetscInt_FMT " tetrahedra; %" PetscInt_FMT " joints at the end; the searches and the rebuilds took %.3g s of wall time\n", ninsertions, ninserted, s.njoints, (double)insert_time));
  PetscCall(PrintTimeSummary(comm, run));
  PetscCall(PrintContactSummary(s, nbodies));
  PetscCall(WriteFragments(s, write ? fdir + "/fragments.csv" : std::string()));
  if (write)
    PetscCall(PetscPrintf(comm, "output: %s/balance.csv (energy and momentum balance; chart: fdem plot %s), %s/scene.xmf (%d frames of all bodies: open it in ParaView, choose the Xdmf3 reader, Apply, then play the animation)\n", dir.c_str(),
                          dir.c_str(), fdir.c_str(), (int)frames.size()));
  PetscCall(SimDestroy(s));
  PetscFunctionReturn(0);
}

} // namespace fdem::driver
