// fdem: runs a scene described in a YAML file (doc/scenes.md).
//
//   mpirun -n N fdem [SCENE.yaml] [PETSc options]   run SCENE (no file: the embedded default scene)
//   fdem check SCENE.yaml [options]                 validate and summarise without running
//   fdem plot DIR                                   DIR/balance.csv -> DIR/balance.png (matplotlib)
//   fdem --help                                     scene keys and every option
//
// The scene's `petsc:` string is inserted into the options database before
// the command line, so an option on the command line wins.
#include "run.hpp"
#include "scene.hpp"
#include "advisor.hpp"
#include "shapes.hpp"

#include <fdem.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <regex>
#include <sstream>
#include <string>

using namespace fdem::driver;

namespace {

const char *kUsage = "usage: mpirun -n N fdem [SCENE.yaml] [PETSc options]   run a scene (no file: the embedded default scene)\n"
                     "       fdem check SCENE.yaml [options]                 validate the scene and print a summary without running\n"
                     "       fdem plot DIR                                   chart DIR/balance.csv into DIR/balance.png (python3 + matplotlib)\n"
                     "       fdem --help                                     this text, the scene keys and every option\n";

const char *kPlot = R"PY(
import csv, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
d = sys.argv[1]
rows = list(csv.DictReader(open(d + "/balance.csv")))
t = [float(r["time"]) for r in rows]
fig, ax = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
for k in ["kinetic", "strain", "contact", "gravity", "fracture", "external_work", "dissipated", "total"]:
    if k == "fracture" and not any(float(r[k]) != 0 for r in rows): continue
    ax[0].plot(t, [float(r[k]) for r in rows], label=k, lw=2 if k == "total" else 1)
ax[0].set_ylabel("energy (J)"); ax[0].legend(fontsize=8); ax[0].grid(alpha=.3)
for k in ["px", "py", "pz"]:
    ax[1].plot(t, [float(r[k]) for r in rows], label=k)
ax[1].set_ylabel("momentum (kg m/s)"); ax[1].set_xlabel("time (s)"); ax[1].legend(fontsize=8); ax[1].grid(alpha=.3)
fig.tight_layout(); fig.savefig(d + "/balance.png", dpi=120)
print("wrote " + d + "/balance.png")
)PY";

// The library names bodies by rigid id ("bodies 3 and 5", "rigid body 3") or by
// name ("deformable body 'slab'", "bodies 'a' and 'b'"): add the scene's names
// and where each body is written, and start with the first body's file:line:col
// ("body 'slab': fracture zone 1": that of the body's fracture_zone[1]).
std::string NameBodies(const Scene &sc, std::string msg) {
  if (msg.rfind(sc.file + ":", 0) == 0) return msg; // the driver's own message, already placed
  std::vector<const Body *> rigid;
  for (const auto &b : sc.bodies)
    if (b.model != "deformable") rigid.push_back(&b); // spheres are rigid bodies
  std::string first;
  auto        by_id = [&](const std::string &id) {
    const size_t i = std::stoul(id);
    if (i >= rigid.size()) return id;
    if (first.empty()) first = rigid[i]->where;
    return id + " ('" + rigid[i]->name + "', " + rigid[i]->where + ")";
  };
  auto by_name = [&](const std::string &name) {
    const Body *b = sc.FindBody(name);
    if (!b) return "'" + name + "'";
    if (first.empty()) first = b->where;
    return "'" + name + "' (" + b->where + ")";
  };
  std::smatch m;
  if (std::regex_search(msg, m, std::regex("bodies (\\d+) and (\\d+)"))) {
    const std::string a = by_id(m[1]), b = by_id(m[2]);
    msg = m.prefix().str() + "bodies " + a + " and " + b + m.suffix().str();
  } else if (std::regex_search(msg, m, std::regex("bodies '([^']*)' and '([^']*)'"))) {
    const std::string a = by_name(m[1]), b = by_name(m[2]);
    msg = m.prefix().str() + "bodies " + a + " and " + b + m.suffix().str();
  }
  else {
    std::string done; // every "rigid body N" (the contact engine names each side by its kind)
    while (std::regex_search(msg, m, std::regex("(rigid body|sphere|clump) (\\d+)"))) {
      done += m.prefix().str() + m[1].str() + " " + by_id(m[2]);
      msg = m.suffix().str();
    }
    msg = done + msg;
  }
  if (std::regex_search(msg, m, std::regex("deformable body '([^']*)'"))) msg = m.prefix().str() + "deformable body " + by_name(m[1]) + m.suffix().str();
  if (std::regex_search(msg, m, std::regex("body '([^']*)': fracture zone (\\d+)")) && first.empty()) { // the library counts a body's zones in the scene's order
    const Body  *b = sc.FindBody(m[1]);
    const size_t z = std::stoul(m[2]);
    if (b && z < b->fracture_zones.size()) first = b->fracture_zones[z].where;
  }
  if (first.empty() && std::regex_search(msg, m, std::regex("fracture material '([^']*)'")) && sc.FindMaterial(m[1])) // a joint's parameters: the material's fracture:
    first = sc.FindMaterial(m[1])->fracture.where;
  if (first.empty() && std::regex_search(msg, m, std::regex("\\bbody '([^']*?)(?: \\(id \\d+\\))?'"))) // any other body named ("element 0 of body 'e' inverted", "body 'a (id 1)': tetrahedron 0 ...")
    msg = m.prefix().str() + "body " + by_name(m[1]) + m.suffix().str();
  if (first.empty() && std::regex_search(msg, m, std::regex("(Rigid body|Sphere|Clump) (.*?) \\(id \\d+\\)"))) // the rigid bodies' set-up ("Rigid body a (id 1): mass inf must be positive")
    msg = m.prefix().str() + m[1].str() + " " + by_name(m[2]) + m.suffix().str();
  if (first.empty() && !sc.petsc.empty()) { // a message naming an option or value of the scene's petsc: string ("Input string abc has no numeric value")
    std::istringstream words(sc.petsc);
    for (std::string w; words >> w;)
      if ((w.size() > 1 && msg.find(w) != std::string::npos) || msg.find("value: " + w) != std::string::npos || msg.find("string " + w + " ") != std::string::npos) { // (a value of one character: PETSc's parse errors end with it)
        first = sc.petsc_where;
        msg += " (the scene's petsc: \"" + sc.petsc + "\")";
        break;
      }
  }
  return (first.empty() ? sc.file : first) + ": " + msg;
}

// The text of a PETSc error: its specific message, else the generic one.
std::string ErrorText(PetscErrorCode ierr) {
  const char *text     = nullptr;
  char       *specific = nullptr;
  PetscErrorMessage(ierr, &text, &specific);
  return specific && specific[0] ? specific : (text ? text : "unknown error");
}

// PETSc's parse errors name the value only ("Input string abc has no numeric value", "Unknown
// logical value: yes2"): put the command line's option that holds it in front.
std::string NameOption(const std::string &msg, int argc, char **argv) {
  std::smatch m;
  if (!std::regex_search(msg, m, std::regex("Input string (.*) has no (numeric|integer) value|Unknown logical value: (.*)"))) return msg;
  const std::string v = m[1].matched ? m[1].str() : m[3].str();
  for (int i = 1; i + 1 < argc; ++i)
    if (argv[i][0] == '-' && v == argv[i + 1]) return std::string(argv[i]) + " " + v + ": " + msg;
  return msg;
}

// The advisor's option (before the scene is read: `model: auto` needs it).
PetscErrorCode AdvisorOptions(PetscReal *strain_limit) {
  PetscFunctionBeginUser;
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "fdem model advisor (doc/advisor.md)", "fdem");
  PetscCall(PetscOptionsReal("-fdem_advise_strain", "Expected strain above which a body needs a deformable mesh (model: auto and fdem check)", "fdem", *strain_limit, strain_limit, nullptr));
  PetscOptionsEnd();
  PetscCheck(*strain_limit > 0 && *strain_limit < PETSC_INFINITY, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "-fdem_advise_strain %g: give a strain > 0 (default 0.01)", (double)*strain_limit);
  PetscFunctionReturn(0);
}

// Reads the scene and its meshes (every rank, the same result). Returns an error message or "".
std::string LoadScene(const char *file, Scene &sc, std::vector<fdem::kernels::TetMesh> &meshes, double strain_limit, std::vector<std::string> &report) {
  try {
    sc = file ? ReadScene(file) : ReadScene("(default scene)", DefaultSceneText());
    ExpandPacks(sc);
    ApplyAuto(sc, strain_limit, report);
    for (const auto &b : sc.bodies) meshes.push_back(b.model == "sphere" ? fdem::kernels::TetMesh{} : ShapeMesh(b)); // a sphere needs no mesh
  } catch (const SceneError &e) {
    return e.what();
  } catch (const std::exception &e) {
    return std::string(file ? file : "(default scene)") + ": " + e.what();
  }
  return "";
}

PetscErrorCode Main(int argc, char **argv, int first, const char *mode, const char *file, int *status) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  if (mode && !std::strcmp(mode, "plot")) {
    PetscCheck(file, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "fdem plot: give the output folder, e.g. fdem plot out");
    if (rank == 0) {
      // the first python3 on PATH that has matplotlib (a pyenv python3 may lack it), else the system's
      const char *python = std::system("python3 -c 'import matplotlib' > /dev/null 2>&1") == 0 ? "python3" : "/usr/bin/python3";
      FILE       *py     = popen((std::string(python) + " - '" + file + "'").c_str(), "w");
      PetscCheck(py, PETSC_COMM_SELF, PETSC_ERR_SYS, "fdem plot: cannot run python3");
      std::fputs(kPlot, py);
      *status = pclose(py) == 0 ? 0 : 1;
    }
    PetscCallMPI(MPI_Bcast(status, 1, MPI_INT, 0, PETSC_COMM_WORLD));
    PetscFunctionReturn(0);
  }
  Scene                                sc;
  std::vector<fdem::kernels::TetMesh> meshes;
  std::vector<std::string>             report;
  PetscReal                            strain_limit = 1e-2;
  if (PetscErrorCode e = AdvisorOptions(&strain_limit)) {
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fdem: error: %s\n", NameOption(ErrorText(e), argc, argv).c_str()));
    *status = 1;
    PetscFunctionReturn(0);
  }
  const std::string err = LoadScene(file, sc, meshes, strain_limit, report);
  if (!err.empty()) {
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fdem: error: %s\n", err.c_str()));
    *status = 1;
    PetscFunctionReturn(0);
  }
  // the scene's options first, then the command line again: the command line wins
  PetscErrorCode ierr         = 0;
  bool           petsc_failed = false;
  if (!sc.petsc.empty()) {
    std::string cl;
    for (int i = first; i < argc; ++i) cl += std::string(" ") + argv[i];
    ierr = PetscOptionsInsertString(nullptr, sc.petsc.c_str());
    if (ierr) petsc_failed = true;
    else ierr = PetscOptionsInsertString(nullptr, cl.c_str());
    // -fdem_advise_strain in the scene's petsc: (unless the command line gives it) decides
    // model: auto too: the scene is read again with it
    PetscReal given = strain_limit;
    if (!ierr) ierr = AdvisorOptions(&given);
    if (!ierr && given != strain_limit) {
      strain_limit = given;
      meshes.clear();
      report.clear();
      const std::string again = LoadScene(file, sc, meshes, strain_limit, report);
      PetscCheck(again.empty(), PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "%s", again.c_str());
    }
  }
  RunOptions o;
  o.check_only = mode && !std::strcmp(mode, "check") ? PETSC_TRUE : PETSC_FALSE;
  if (o.check_only) {
    std::vector<std::string> advice;
    try {
      advice = AdviceReport(sc, strain_limit, 20);
    } catch (const std::exception &e) {
      advice = {std::string("model advice: ") + e.what()};
    }
    report.insert(report.end(), advice.begin(), advice.end());
  }
  for (const auto &line : report) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s\n", line.c_str()));
  if (!ierr) ierr = RunOptionsFromCommandLine(PETSC_COMM_WORLD, o); // (its errors, as the run's, are named after the scene)
  if (!ierr) ierr = RunScene(PETSC_COMM_WORLD, sc, std::move(meshes), o);
  if (ierr) {
    const std::string what = NameOption(ErrorText(ierr), argc, argv);
    const std::string msg  = petsc_failed ? sc.petsc_where + ": petsc: \"" + sc.petsc + "\": " + what : NameBodies(sc, what);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "\nfdem: error: %s\n", msg.c_str()));
    *status = 1;
  }
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv) {
  // positional arguments come first: [check|plot] [SCENE|DIR]; options follow
  int         first = 1;
  const char *mode = nullptr, *file = nullptr;
  bool        help = false;
  for (int i = 1; i < argc; ++i)
    if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h") || !std::strcmp(argv[i], "help")) help = true;
  if (first < argc && (!std::strcmp(argv[first], "check") || !std::strcmp(argv[first], "plot"))) mode = argv[first++];
  if (first < argc && argv[first][0] != '-') file = argv[first++];
  if (help) {
    std::printf("%s\n%s\nOptions (every PETSc and fdem option; the listing below comes from checking the default scene):\n", kUsage, SceneKeysHelp());
    std::fflush(stdout);
  }
  // PETSc sees the options only (and -help when asked)
  std::vector<char *> args = {argv[0]};
  for (int i = first; i < argc; ++i)
    if (std::strcmp(argv[i], "--help") && std::strcmp(argv[i], "-h") && std::strcmp(argv[i], "help")) args.push_back(argv[i]);
  static char helpopt[] = "-help", noprog[] = "-fdem_progress", no[] = "0";
  if (help) args.insert(args.end(), {helpopt, noprog, no});
  int    pargc = (int)args.size();
  args.push_back(nullptr); // argv[argc] == NULL, as MPI_Init reads it
  char **pargv = args.data();
  PetscCall(PetscInitialize(&pargc, &pargv, nullptr, nullptr));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  PetscCall(PetscLogDefaultBegin());
  PetscCall(FDEMInitializePackage());
  int status = 0;
  if (help) {
    mode = "check";
    file = nullptr;
  }
  const PetscErrorCode ierr = Main(pargc, pargv, 1, mode, file, &status);
  if (ierr) {
    PetscPrintf(PETSC_COMM_WORLD, "fdem: error: %s\n", ErrorText(ierr).c_str());
    status = 1;
  }
  PetscCall(PetscFinalize());
  return status;
}
