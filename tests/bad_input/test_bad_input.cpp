// Bad input files through every path of their kind (tests/fuzz/inputs.hpp: a
// .msh file goes through the reader and the rigid and the deformable path),
// driven by the table cases.txt: each case asserts the error message (it names
// the file and line and what is wrong), that every rank got the same error
// (collective) and, under -malloc_dump (CTest), that nothing leaks after it.
//   test_bad_input -cases cases.txt -dir <folder of the files>
#include "../fuzz/inputs.hpp"

#include <fstream>
#include <functional>
#include <sstream>

#include "../common/check.hpp"

namespace {

std::string Trim(const std::string &s) {
  const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

struct Case {
  std::string file, paths, expected;
  int         line;
};

// Same value on every rank?
PetscErrorCode AllSame(MPI_Comm comm, unsigned long v, bool *same) {
  unsigned long lo, hi;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(&v, &lo, 1, MPI_UNSIGNED_LONG, MPI_MIN, comm));
  PetscCallMPI(MPI_Allreduce(&v, &hi, 1, MPI_UNSIGNED_LONG, MPI_MAX, comm));
  *same = lo == hi;
  PetscFunctionReturn(0);
}

PetscErrorCode RunCase(MPI_Comm comm, const Case &c, const std::string &dir) {
  const std::string        path = dir + "/" + c.file;
  const fdem_inputs::Kind *k    = fdem_inputs::FindKind("", path);
  PetscFunctionBeginUser;
  CHECK(k, "cases.txt:%d: no input kind takes %s", c.line, c.file.c_str());
  if (!k) PetscFunctionReturn(0);
  const bool        warn   = c.expected.rfind("warning: ", 0) == 0;
  const std::string accept = warn || c.expected == "accepted" ? "accepted" : "";
  if (warn) {  // the reader's warning (the paths print it)
    std::string got;
    try {
      for (const auto &w : fdem::kernels::ReadGmsh(path).warnings) got += w;
    } catch (const std::exception &e) {
      got = e.what();
    }
    CHECK(got.find(c.expected.substr(9)) != std::string::npos, "%s: expected the warning \"%s\", got \"%s\"", c.file.c_str(), c.expected.substr(9).c_str(), got.c_str());
  }
  for (const auto &p : k->paths) {
    if (c.paths != "both" && c.paths != p.name) continue;
    std::string msg;
    bool        same;
    PetscCall(fdem_inputs::RunPath(comm, p, path.c_str(), &msg));
    PetscCall(AllSame(comm, std::hash<std::string>()(msg), &same));
    CHECK(same, "%s (%s): the ranks ended differently (not collective)", c.file.c_str(), p.name);
    if (!accept.empty()) {
      CHECK(msg.empty(), "%s (%s): expected it accepted, got: %s", c.file.c_str(), p.name, msg.c_str());
      if (msg.empty()) PetscCall(PetscPrintf(comm, "ok: %s (%s) accepted\n", c.file.c_str(), p.name));
    } else {
      const bool ok = msg.find(c.expected) != std::string::npos;
      CHECK(ok, "%s (%s): expected an error containing \"%s\", got \"%s\"", c.file.c_str(), p.name, c.expected.c_str(), msg.empty() ? "no error" : msg.c_str());
      if (ok) PetscCall(PetscPrintf(comm, "ok: %s (%s) -> %s\n", c.file.c_str(), p.name, msg.c_str()));
    }
  }
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv) {
  char cases[PETSC_MAX_PATH_LEN] = "", dir[PETSC_MAX_PATH_LEN] = "";
  int  ncases = 0;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "fdem bad-input tests", "test_bad_input");
  PetscCall(PetscOptionsString("-cases", "Table of cases: file | paths | expected", "test_bad_input", cases, cases, sizeof(cases), nullptr));
  PetscCall(PetscOptionsString("-dir", "Folder of the case files", "test_bad_input", dir, dir, sizeof(dir), nullptr));
  PetscOptionsEnd();
  std::ifstream in(cases);
  PetscCheck(in, PETSC_COMM_WORLD, PETSC_ERR_FILE_OPEN, "cannot open -cases %s", cases);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (Trim(line).empty() || Trim(line)[0] == '#') continue;
    const auto a = line.find('|'), b = a == std::string::npos ? a : line.find('|', a + 1);
    PetscCheck(b != std::string::npos, PETSC_COMM_WORLD, PETSC_ERR_FILE_UNEXPECTED, "%s:%d: expected <file> | <paths> | <expected>", cases, n);
    const Case c{Trim(line.substr(0, a)), Trim(line.substr(a + 1, b - a - 1)), Trim(line.substr(b + 1)), n};
    PetscCheck(c.paths == "both" || c.paths == "rigid" || c.paths == "deformable", PETSC_COMM_WORLD, PETSC_ERR_FILE_UNEXPECTED, "%s:%d: paths must be both, rigid or deformable", cases, n);
    PetscCall(RunCase(PETSC_COMM_WORLD, c, dir));
    ++ncases;
  }
  CHECK(ncases >= 40, "only %d cases in %s", ncases, cases);
  if (failures) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d FAILURES\n", failures));
  else PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d bad-input cases passed\n", ncases));
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
