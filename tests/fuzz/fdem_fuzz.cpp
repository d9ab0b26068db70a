// Fuzz driver: runs input files through every path of their kind
// (tests/fuzz/inputs.hpp; a .msh file: the reader, then the rigid path
// FDEMRigidAddBodyFromMesh and the deformable path FDEMDeformableSetMeshFromGmsh
// + FDEMDeformableSetUp) and prints, for each file and path, one line on rank 0:
//   <file>: accepted <path>
//   <file>: rejected <path>: <error message>
// Exit 0 when every path ended that way; a crash, hang, sanitizer report or
// leak (-malloc_dump) is the harness's to see (scripts/fuzz.sh, doc/hardening.md).
//   fdem_fuzz -input file | -input_list list [-kind msh] [-paths rigid,deformable] [-expect accepted|rejected]
// -input_list: a file naming one input per line (many inputs in one process).
// -expect (for CTest): exit 1 unless every path accepted every file / rejected
// it with a message naming it as file:line.
#include "inputs.hpp"

#include <cstring>
#include <fstream>
#include <regex>

namespace {

// Runs one file through the chosen paths; counts the paths that did not end as expected.
PetscErrorCode RunFile(const std::string &input, const char *kind, char **paths, PetscInt npaths, const char *expect, int *wrong) {
  PetscFunctionBeginUser;
  const fdem_inputs::Kind *k = fdem_inputs::FindKind(kind, input);
  PetscCheck(k, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "%s: no input kind %s (known: msh)", input.c_str(), kind[0] ? kind : "takes this extension");
  for (PetscInt i = 0; i < npaths; ++i) {
    bool known = false;
    for (const auto &p : k->paths) known = known || !std::strcmp(p.name, paths[i]);
    PetscCheck(known, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "-paths: kind %s has no path %s", k->name, paths[i]);
  }
  // file:line: as the reader writes it (the path as given, a colon, digits, a colon)
  const std::regex where(std::regex_replace(input, std::regex(R"([.^$|()\[\]{}*+?\\])"), R"(\$&)") + ":[0-9]+:");
  for (const auto &p : k->paths) {
    bool run = npaths == 0;
    for (PetscInt i = 0; i < npaths; ++i) run = run || !std::strcmp(p.name, paths[i]);
    if (!run) continue;
    std::string msg;
    PetscCall(fdem_inputs::RunPath(PETSC_COMM_WORLD, p, input.c_str(), &msg));
    if (msg.empty()) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s: accepted %s\n", input.c_str(), p.name));
    else PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s: rejected %s: %s\n", input.c_str(), p.name, msg.c_str()));
    if (!std::strcmp(expect, "accepted")) *wrong += !msg.empty();
    if (!std::strcmp(expect, "rejected")) *wrong += !std::regex_search(msg, where);
  }
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv) {
  char      input[PETSC_MAX_PATH_LEN] = "", list[PETSC_MAX_PATH_LEN] = "", kind[64] = "", expect[16] = "", *paths[8];
  PetscInt  npaths = 8;
  PetscBool has_paths;
  int       wrong = 0;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "fdem fuzz driver", "fdem_fuzz");
  PetscCall(PetscOptionsString("-input", "The input file", "fdem_fuzz", input, input, sizeof(input), nullptr));
  PetscCall(PetscOptionsString("-input_list", "A file naming one input file per line", "fdem_fuzz", list, list, sizeof(list), nullptr));
  PetscCall(PetscOptionsString("-kind", "Input kind (msh); default: from the file's extension", "fdem_fuzz", kind, kind, sizeof(kind), nullptr));
  PetscCall(PetscOptionsStringArray("-paths", "Paths to run (default: all of the kind's)", "fdem_fuzz", paths, &npaths, &has_paths));
  PetscCall(PetscOptionsString("-expect", "accepted or rejected: exit 1 if any path ends otherwise (rejected: with file:line)", "fdem_fuzz", expect, expect, sizeof(expect), nullptr));
  PetscOptionsEnd();
  if (!has_paths) npaths = 0;
  PetscCheck(!expect[0] || !std::strcmp(expect, "accepted") || !std::strcmp(expect, "rejected"), PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "-expect %s: use accepted or rejected", expect);
  std::vector<std::string> inputs;
  if (input[0]) inputs.push_back(input);
  if (list[0]) {
    std::ifstream in(list);
    PetscCheck(in, PETSC_COMM_WORLD, PETSC_ERR_FILE_OPEN, "-input_list: cannot open %s", list);
    for (std::string line; std::getline(in, line);)
      if (!line.empty()) inputs.push_back(line);
  }
  PetscCheck(!inputs.empty(), PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "give -input <file> or -input_list <file of names>");
  for (const auto &f : inputs) PetscCall(RunFile(f, kind, paths, npaths, expect, &wrong));
  for (PetscInt i = 0; i < npaths; ++i) PetscCall(PetscFree(paths[i]));
  PetscCall(PetscFinalize());
  return wrong ? 1 : 0;
}
