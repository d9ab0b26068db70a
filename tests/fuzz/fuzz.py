#!/usr/bin/env python3
"""Mutation fuzzing of fdem's input readers (run through scripts/fuzz.sh).

Each input is a random seed file (valid and broken inputs), applies a few
random mutations (numbers swapped for extreme values, lines deleted, doubled,
swapped or spliced from another file, bytes flipped, truncation, ...). The
driver (tests/fuzz/fdem_fuzz, -malloc_dump) reads a batch of inputs per
process under mpiexec, 1 or 2 ranks in turn, with a time limit; a batch that
does not end cleanly is re-run one input per process. Every input is classified:

  accepted          every path accepted the file
  rejected_located  rejected, each message names the file as file:line:
  rejected_unlocated rejected by a message without file:line
  crash             ended by a signal or a non-zero exit (abort, uncaught exception)
  sanitizer         an AddressSanitizer / UndefinedBehaviorSanitizer report
  leak              PETSc -malloc_dump found memory not freed after the run
  hang              still running at the time limit

Inputs of the last four classes and of rejected_unlocated are kept under
OUT/<class>/ with the driver's output, to replay with
  mpiexec -n <ranks> fdem_fuzz -input OUT/<class>/<file>
The driver picks the input kind from the file extension, so seeds of a new
kind (e.g. .yaml scenes) join by being in a seed folder.
Scene mode (--scenes, scripts/fuzz.sh MINUTES --scenes): the seeds are YAML
scene files and --driver is the `fdem` driver itself. Each mutated scene is
written into its seed's folder under a temporary name (so that relative mesh
paths resolve), run there as `fdem check INPUT` and as
`fdem INPUT -ts_max_steps 3 -fdem_output none -fdem_progress 0`, one process
per run, 1 or 2 ranks in turn, and removed. Mutations know YAML: numbers
become extreme values, keys are deleted, duplicated or renamed, values are
swapped between keys or taken from other seeds, flow lists shortened or
lengthened, braces and brackets broken, lines swapped, deleted or re-indented;
and a scene's `petsc:` string is given one of the options the sources read
(and a few of PETSc's TS options) with an extreme or odd value.
An input is classified by its worst run: rejected_located if each message
`fdem: error: ...` names the input as file:line, crash if a run ended by a
signal, a PETSc error trace or a non-zero exit without such a message. Kept
inputs (OUT/<class>/input_N.yaml with the log naming the seed folder) replay
with `cd SEED_FOLDER && mpiexec -n <ranks> fdem check input_N.yaml`.
Standard library only.
"""
import argparse
import collections
import os
import random
import re
import shutil
import subprocess
import sys
import time

INTERESTING = [
    "0", "-0", "1", "-1", "2", "3", "4", "5", "7", "8", "11", "15", "-2", "255", "256", "65535",
    "2147483647", "2147483648", "-2147483648", "4294967295", "4294967296", "1000000000000",
    "9223372036854775807", "-9223372036854775808", "9223372036854775806", "18446744073709551616",
    "99999999999999999999999", "1e308", "1e309", "-1e308", "1e-320", "4.9e-324", "1e300", "-1e300",
    "nan", "-nan", "inf", "-inf", "NaN", "0x10", "1e", "0.5", "2.2", "4.1", "3.0", "", "abc", "\"", "$",
]
SECTION_LINES = ["$MeshFormat", "$EndMeshFormat", "$Nodes", "$EndNodes", "$Elements", "$EndElements",
                 "$Entities", "$EndEntities", "$PhysicalNames", "$EndPhysicalNames", "$Comments", "$End"]
NUMBER = re.compile(rb"[-+]?(?:\d+\.?\d*(?:[eE][-+]?\d+)?|\.\d+(?:[eE][-+]?\d+)?|nan|inf)", re.I)


def mutate(data, pool, rng):
    lines = data.split(b"\n")
    kind = rng.randrange(16)
    if kind <= 3:  # a number becomes an extreme or nearby value
        nums = list(NUMBER.finditer(data))
        if nums:
            m = rng.choice(nums)
            tok = m.group(0)
            if kind == 0 or kind == 1:
                new = rng.choice(INTERESTING).encode()
            else:
                try:
                    v = int(tok)
                    new = str(rng.choice([v + 1, v - 1, -v, 2 * v, v // 2, v + 1000])).encode()
                except ValueError:
                    new = rng.choice([b"-" + tok, tok + b"0", tok[:-1] or b"0"])
            return data[:m.start()] + new + data[m.end():]
    if kind == 4 and len(lines) > 1:  # delete a line
        del lines[rng.randrange(len(lines))]
    elif kind == 5:  # duplicate a line
        i = rng.randrange(len(lines))
        lines.insert(i, lines[i])
    elif kind == 6 and len(lines) > 1:  # swap two lines
        i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
    elif kind == 7:  # a line from another file
        other = rng.choice(pool).split(b"\n")
        lines.insert(rng.randrange(len(lines) + 1), rng.choice(other))
    elif kind == 8:  # splice: head of this file, tail of another
        other = rng.choice(pool)
        return data[:rng.randrange(len(data) + 1)] + other[rng.randrange(len(other) + 1):]
    elif kind == 9:  # truncate
        return data[:rng.randrange(len(data) + 1)]
    elif kind == 10 and data:  # flip, insert or delete a byte
        i = rng.randrange(len(data))
        op = rng.randrange(3)
        b = bytes([rng.choice([0, 9, 10, 13, 32, 34, 36, 45, 46, 48, 57, 101, 255, rng.randrange(256)])])
        if op == 0:
            return data[:i] + b + data[i + 1:]
        if op == 1:
            return data[:i] + b + data[i:]
        return data[:i] + data[i + 1:]
    elif kind == 11:  # a section header or end line
        lines.insert(rng.randrange(len(lines) + 1), rng.choice(SECTION_LINES).encode())
    elif kind == 12:  # repeat a block of lines
        i = rng.randrange(len(lines))
        j = min(len(lines), i + rng.randrange(1, 12))
        lines[j:j] = lines[i:j] * rng.randrange(1, 4)
    elif kind == 13:  # drop or add a token on a line
        i = rng.randrange(len(lines))
        toks = lines[i].split(b" ")
        if toks and rng.random() < 0.5:
            del toks[rng.randrange(len(toks))]
        else:
            toks.insert(rng.randrange(len(toks) + 1), rng.choice(INTERESTING).encode())
        lines[i] = b" ".join(toks)
    elif kind == 14:  # whitespace and line ends
        i = rng.randrange(len(lines))
        lines[i] = rng.choice([lines[i].replace(b" ", b"\t"), lines[i] + b"\r", b"  " + lines[i] + b"  ", lines[i].replace(b" ", b"  ")])
    else:  # swap two numbers of one line
        i = rng.randrange(len(lines))
        toks = lines[i].split(b" ")
        if len(toks) > 1:
            a, b = rng.randrange(len(toks)), rng.randrange(len(toks))
            toks[a], toks[b] = toks[b], toks[a]
            lines[i] = b" ".join(toks)
    return b"\n".join(lines)


def report(out, timed_out, rc):
    """The run-level class, or None if the process ended normally and clean."""
    if timed_out:
        return "hang"
    if "ERROR: AddressSanitizer" in out or "runtime error:" in out or "ERROR: LeakSanitizer" in out:
        return "sanitizer"
    if re.search(r"^\[ *\d+\] \d+ bytes ", out, re.M):
        return "leak"
    if rc != 0:
        return "crash"
    return None


def classify_file(path, out):
    """Class of one file from a clean run's output lines '<file>: accepted|rejected <path>[: msg]'."""
    results = re.findall(r"^" + re.escape(path) + r": (accepted|rejected) (\w+)(?:: (.*))?$", out, re.M)
    if not results:
        return "crash"
    where = re.compile(re.escape(path) + r":\d+:")
    if any(r[0] == "rejected" and not where.search(r[2]) for r in results):
        return "rejected_unlocated"
    if any(r[0] == "rejected" for r in results):
        return "rejected_located"
    return "accepted"


def run(cmd, env, timeout):
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=env, timeout=timeout)
        return p.returncode, p.stdout.decode(errors="replace"), False
    except subprocess.TimeoutExpired as e:
        return -1, (e.stdout or b"").decode(errors="replace"), True


SCENE_VALUES = [
    "0", "-0", "-1", "1", "2", "1e308", "-1e308", "1e309", "1e-308", "4.9e-324", "1e300", "1e-300", "1e15", "1e16",
    "2147483648", "9223372036854775807", "99999999999999999999999", "nan", ".nan", "inf", ".inf", "-.inf",
    "0.5", "0.4999999", "-0.9999", "89.999", "90", "abc", "''", "~", "null", "[]", "{}", "true", "auto", "[0, 0, 0]",
    "[1e308, 1e308, 1e308]", "[x, 0, 1]", "{box: [1, 1, 1]}", "{sphere: 0.001}", "1e-12", "0.001",
]
KEY = re.compile(rb"(?<![\w.-])([A-Za-z_][A-Za-z0-9_]*)[ \t]*:(?=[ \t\n{\[])")
WORD = re.compile(rb"(?<![\w.])[A-Za-z_][A-Za-z0-9_.]*(?![\w.]*:)")


def value_end(data, i):
    """End of the YAML value starting at i: a ',' or closing bracket at depth 0, or the line end."""
    depth = 0
    for j in range(i, len(data)):
        c = data[j:j + 1]
        if c in (b"[", b"{"):
            depth += 1
        elif c in (b"]", b"}"):
            if depth == 0:
                return j
            depth -= 1
        elif (c == b"," or c == b"\n") and depth == 0:
            return j
    return len(data)


def entries(data):
    """(key start, value start, value end) of every `key: value`."""
    return [(m.start(), m.end(), value_end(data, m.end())) for m in KEY.finditer(data)]


def flow_lists(data):
    """(start, end) of every [...] list, end at its closing bracket."""
    out = []
    for m in re.finditer(rb"\[", data):
        e = value_end(data, m.start() + 1)
        if e < len(data) and data[e:e + 1] == b"]":
            out.append((m.start(), e))
    return out


def option_names():
    """The options fdem reads (the strings "-fdem_..." and "-ts_fdem_..." in src/ and apps/, as
    tests/driver/help_options.py finds them) and the TS options the driver takes, without the
    tests' kill switch."""
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    names = set()
    for top in ("src", "apps"):
        for d, _, files in os.walk(os.path.join(root, top)):
            for f in files:
                if f.endswith((".cpp", ".hpp", ".h")):
                    with open(os.path.join(d, f), errors="replace") as fh:
                        names |= set(re.findall(r'"(-(?:ts_)?fdem_[a-z0-9_]+)', fh.read()))
    names |= {"-ts_dt", "-ts_max_time", "-ts_max_steps", "-ts_type", "-ts_init_time", "-ts_exact_final_time", "-ts_adapt_type", "-restart"}
    return sorted(names - {"-fdem_checkpoint_kill"})


OPTIONS = option_names()
OPTION_VALUES = SCENE_VALUES + ["yes2", "1,2", "1,2,3,4", "0,0,-9.81", "nan,0,0", "4294967297", "-2147483649", "1.5", "cd", "none"]


def mutate_scene(data, pool, rng):
    kind = rng.randrange(19)
    if kind == 18:  # the scene's petsc: string, one option with an extreme or odd value
        kept = [l for l in data.split(b"\n") if not l.startswith(b"petsc:")]
        opt = '%s %s' % (rng.choice(OPTIONS), rng.choice(OPTION_VALUES))
        return b"\n".join(kept + [b'petsc: "' + opt.replace('"', "").encode() + b'"'])
    lines = data.split(b"\n")
    ents = entries(data)
    if kind <= 3:  # a number (or a value) becomes an extreme or odd one
        nums = list(NUMBER.finditer(data))
        if nums and kind < 3:
            m = rng.choice(nums)
            new = rng.choice(SCENE_VALUES if kind < 2 else INTERESTING).encode()
            return data[:m.start()] + new + data[m.end():]
        if ents:
            k, v, e = rng.choice(ents)
            return data[:v] + b" " + rng.choice(SCENE_VALUES).encode() + data[e:]
    if kind == 4 and ents:  # delete a key with its value
        k, v, e = rng.choice(ents)
        if data[e:e + 1] == b",":
            e += 1
        return data[:k] + data[e:]
    if kind == 5 and ents:  # duplicate a key with its value
        k, v, e = rng.choice(ents)
        sep = b", " if data[e:e + 1] in (b",", b"}") else b"\n" + re.match(rb"[ \t-]*", data[data.rfind(b"\n", 0, k) + 1:]).group(0).replace(b"-", b" ")
        return data[:e] + sep + data[k:e] + data[e:]
    if kind == 6 and len(ents) > 1:  # swap the values of two keys
        (k1, v1, e1), (k2, v2, e2) = sorted(rng.sample(ents, 2))
        if e1 <= k2:
            return data[:v1] + data[v2:e2] + data[e1:v2] + data[v1:e1] + data[e2:]
    if kind == 7 and ents:  # rename a key (to one of any seed)
        k, v, e = rng.choice(ents)
        others = [m.group(1) for m in KEY.finditer(rng.choice(pool))]
        if others:
            return data[:k] + rng.choice(others) + b":" + data[v:]
    if kind == 8 and ents:  # a value from another seed's entry
        other = rng.choice(pool)
        oe = entries(other)
        if oe:
            k, v, e = rng.choice(ents)
            ok, ov, oe_ = rng.choice(oe)
            return data[:v] + other[ov:oe_] + data[e:]
    if kind == 9:  # a list shortened or lengthened
        lists = flow_lists(data)
        if lists:
            a, b = rng.choice(lists)
            items, depth, start = [], 0, a + 1
            for j in range(a + 1, b):
                c = data[j:j + 1]
                depth += c in (b"[", b"{")
                depth -= c in (b"]", b"}")
                if c == b"," and depth == 0:
                    items.append(data[start:j].strip())
                    start = j + 1
            items.append(data[start:b].strip())
            op = rng.randrange(4)
            if op == 0:
                del items[rng.randrange(len(items))]
            elif op == 1:
                items.insert(rng.randrange(len(items) + 1), rng.choice(items))
            elif op == 2:
                items.append(rng.choice(SCENE_VALUES).encode())
            else:
                items = items * rng.choice([2, 10, 100])
            return data[:a + 1] + b", ".join(items) + data[b:]
    if kind == 10 and data:  # a brace, bracket, comma or colon broken
        marks = [i for i in range(len(data)) if data[i:i + 1] in b"{}[],:"]
        if marks:
            i = rng.choice(marks)
            op = rng.randrange(3)
            if op == 0:
                return data[:i] + data[i + 1:]
            return data[:i] + rng.choice([b"{", b"}", b"[", b"]", b",", b":", b"- "]) + data[i + (op == 1):]
    if kind == 11 and len(lines) > 1:  # swap two lines
        i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
        return b"\n".join(lines)
    if kind == 12 and len(lines) > 1:  # delete a line
        del lines[rng.randrange(len(lines))]
        return b"\n".join(lines)
    if kind == 13:  # duplicate a line or a line of another seed
        i = rng.randrange(len(lines))
        lines.insert(i, lines[i] if rng.random() < 0.5 else rng.choice(rng.choice(pool).split(b"\n")))
        return b"\n".join(lines)
    if kind == 14:  # indentation changed
        i = rng.randrange(len(lines))
        lines[i] = rng.choice([b"  " + lines[i], lines[i][2:] if lines[i].startswith(b"  ") else b" " + lines[i],
                               b"\t" + lines[i], lines[i].lstrip(), b"- " + lines[i]])
        return b"\n".join(lines)
    if kind == 15:  # a word (model, shape, scheme, material or body name, ...) for another seed's word
        words = list(WORD.finditer(data))
        others = [m.group(0) for m in WORD.finditer(rng.choice(pool))]
        if words and others:
            m = rng.choice(words)
            return data[:m.start()] + rng.choice(others) + data[m.end():]
    if kind == 16 and len(lines) > 1:  # a block of lines repeated (another body, material, ...)
        i = rng.randrange(len(lines))
        j = min(len(lines), i + rng.randrange(1, 6))
        lines[j:j] = lines[i:j] * rng.randrange(1, 3)
        return b"\n".join(lines)
    return mutate(data, pool, rng)  # the byte and line mutations of the mesh mode


def run_group(cmd, env, timeout, cwd):
    """Runs cmd in its own process group (the whole group is killed at the time limit)."""
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=env, cwd=cwd, start_new_session=True)
    try:
        out, _ = p.communicate(timeout=timeout)
        return p.returncode, out.decode(errors="replace"), False
    except subprocess.TimeoutExpired:
        try:
            os.killpg(p.pid, 9)
        except ProcessLookupError:
            pass
        out, _ = p.communicate()
        return -1, out.decode(errors="replace"), True


SCENE_CLASSES = ["accepted", "rejected_located", "rejected_unlocated", "crash", "hang"]


def classify_scene(name, out, rc, timed_out):
    """Class of one driver run on the scene file `name` (its base name)."""
    if timed_out:
        return "hang"
    errors = re.findall(r"^fdem: error: (.*)$", out, re.M)
    if re.search(r"PETSC ERROR|Segmentation|signal \d|terminate called|Abort|MPI_ABORT|core dumped", out):
        return "crash"
    if rc != 0 and not errors:
        return "crash"
    if errors:
        return "rejected_located" if all(re.match(re.escape(name) + r":\d+:", e) for e in errors) else "rejected_unlocated"
    return "accepted"


def scene_main(args):
    """The scene mode: the fdem driver per input (see the module's text)."""
    seed = args.seed if args.seed is not None else int(time.time())
    rng = random.Random(seed)
    seeds = []
    for d in args.seeds:
        for f in sorted(os.listdir(d)):
            if f.endswith(".yaml") and not f.startswith(".fuzz-"):
                with open(os.path.join(d, f), "rb") as fh:  # without comment lines: mutations hit the scene
                    text = b"\n".join(l for l in fh.read().split(b"\n") if not l.lstrip().startswith(b"#"))
                    seeds.append((os.path.abspath(d), text))
    if not seeds:
        sys.exit("fuzz.py: no .yaml scene files in %s" % " ".join(args.seeds))
    pool = [s[1] for s in seeds]
    folders = sorted(set(s[0] for s in seeds))
    ranks = [int(r) for r in args.ranks.split(",")]
    shutil.rmtree(args.out, ignore_errors=True)
    os.makedirs(args.out)
    env = dict(os.environ)
    env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
    prefix = ["taskset", "-c", args.taskset] if args.taskset else []
    bind = ["--bind-to", "none"] if args.taskset else []
    counts = collections.Counter()
    by_ranks = collections.Counter()
    end = time.time() + 60 * args.minutes
    n = 0
    print("fuzz (scenes): %d seeds, ranks %s, timeout %gs per run, random seed %d, %g minutes"
          % (len(seeds), args.ranks, args.timeout, seed, args.minutes), flush=True)
    worst = {c: i for i, c in enumerate(SCENE_CLASSES)}
    while time.time() < end:
        np_ = ranks[n % len(ranks)]
        folder = rng.choice(folders)  # each seed folder as often (tests/driver/bad has many)
        data = rng.choice([s[1] for s in seeds if s[0] == folder])
        for _ in range(rng.choice([1, 1, 2, 3, 4])):
            data = mutate_scene(data, pool, rng)
        name = ".fuzz-%d-%07d.yaml" % (os.getpid(), n)
        path = os.path.join(folder, name)
        with open(path, "wb") as fh:
            fh.write(data)
        launch = prefix + [args.mpiexec] + bind + ["-n", str(np_), args.driver]
        c, logs = "accepted", []
        try:
            for cmd in (launch[:-1] + [args.driver, "check", name, "-fdem_progress", "0"],
                        launch + [name, "-ts_max_steps", "3", "-fdem_output", "none", "-fdem_progress", "0"]):
                t0 = time.time()
                rc, out, timed_out = run_group(cmd, env, args.timeout, folder)
                ci = classify_scene(name, out, rc, timed_out)
                logs.append("$ cd %s && %s\n(exit %d%s, %.1f s: %s)\n%s\n" % (folder, " ".join(cmd), rc, ", timed out" if timed_out else "", time.time() - t0, ci, out))
                if worst[ci] > worst[c]:
                    c = ci
        finally:
            os.remove(path)
        counts[c] += 1
        by_ranks[(c, np_)] += 1
        if c not in ("accepted", "rejected_located"):
            keep = os.path.join(args.out, c)
            os.makedirs(keep, exist_ok=True)
            base = "input_%07d" % n
            with open(os.path.join(keep, base + ".yaml"), "wb") as fh:
                fh.write(data)
            with open(os.path.join(keep, base + ".np%d.log" % np_), "w") as fh:
                fh.write("(the input ran as %s in %s)\n" % (name, folder) + "".join(logs).replace(name, base + ".yaml"))
            print("fuzz: %s (np %d, seed folder %s): %s, kept in %s" % (base, np_, folder, c, keep), flush=True)
        elif c == "accepted" and len(pool) < 500:
            pool.append(data)  # accepted mutants seed further mutations
            seeds.append((folder, data))
        n += 1
        if n % 50 == 0:
            print("fuzz: %d inputs: %s" % (n, dict(counts)), flush=True)
    labels = {"accepted": "accepted", "rejected_located": "rejected with file:line",
              "rejected_unlocated": "rejected without file:line", "crash": "crash", "hang": "hang"}
    lines = ["fuzz (scenes) summary: %d inputs (2 runs each) in %g minutes (random seed %d)" % (n, args.minutes, seed)]
    for c in SCENE_CLASSES:
        lines.append("  %-27s %6d   (np 1: %d, np 2: %d)" % (labels[c], counts[c], by_ranks[(c, 1)], by_ranks[(c, 2)]))
    text = "\n".join(lines)
    print(text)
    with open(os.path.join(args.out, "summary.txt"), "w") as fh:
        fh.write(text + "\n")
    sys.exit(1 if sum(counts[c] for c in SCENE_CLASSES[2:]) else 0)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--driver", required=True, help="the fdem_fuzz executable (--scenes: the fdem driver)")
    ap.add_argument("--minutes", type=float, required=True)
    ap.add_argument("--seeds", nargs="+", required=True, help="folders of seed files")
    ap.add_argument("--ext", nargs="+", default=[".msh"], help="seed file extensions (input kinds)")
    ap.add_argument("--out", required=True, help="folder for the kept inputs and the summary")
    ap.add_argument("--ranks", default="1,2", help="rank counts, used in turn")
    ap.add_argument("--timeout", type=float, default=30.0, help="seconds per file before a run counts as a hang")
    ap.add_argument("--batch", type=int, default=25, help="files per driver process (a dirty batch is re-run file by file)")
    ap.add_argument("--seed", type=int, default=None, help="random seed (default: from the clock)")
    ap.add_argument("--mpiexec", default="mpiexec", help="MPI launcher")
    ap.add_argument("--scenes", action="store_true", help="fuzz YAML scene seeds with the fdem driver, one process per run")
    ap.add_argument("--taskset", default=None, help="--scenes: pin every run to these CPUs (taskset -c, mpiexec --bind-to none)")
    args = ap.parse_args()
    if args.scenes:
        scene_main(args)

    seed = args.seed if args.seed is not None else int(time.time())
    rng = random.Random(seed)
    seeds = []
    for d in args.seeds:
        for f in sorted(os.listdir(d)):
            if os.path.splitext(f)[1] in args.ext:
                with open(os.path.join(d, f), "rb") as fh:
                    seeds.append((os.path.splitext(f)[1], fh.read()))
    if not seeds:
        sys.exit("fuzz.py: no seed files with extension %s in %s" % (" ".join(args.ext), " ".join(args.seeds)))
    pool = [s[1] for s in seeds]
    ranks = [int(r) for r in args.ranks.split(",")]
    work = os.path.join(args.out, "work")
    shutil.rmtree(args.out, ignore_errors=True)
    os.makedirs(work)
    env = dict(os.environ)
    env.setdefault("ASAN_OPTIONS", "halt_on_error=1:detect_leaks=0:abort_on_error=0")
    env.setdefault("UBSAN_OPTIONS", "halt_on_error=1:print_stacktrace=1")
    env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")

    counts = collections.Counter()
    by_ranks = collections.Counter()
    end = time.time() + 60 * args.minutes
    n = batches = 0
    print("fuzz: %d seeds, ranks %s, batches of %d, timeout %gs per file, random seed %d, %g minutes"
          % (len(seeds), args.ranks, args.batch, args.timeout, seed, args.minutes), flush=True)
    while time.time() < end:
        np_ = ranks[batches % len(ranks)]
        batches += 1
        files = []
        for _ in range(args.batch):
            ext, data = rng.choice(seeds)
            for _ in range(rng.choice([1, 1, 2, 3, 4])):
                data = mutate(data, pool, rng)
            path = os.path.join(work, "input_%07d%s" % (n + len(files), ext))
            with open(path, "wb") as fh:
                fh.write(data)
            files.append((path, ext, data))
        listing = os.path.join(work, "batch.txt")
        with open(listing, "w") as fh:
            fh.write("".join(f[0] + "\n" for f in files))
        launch = [args.mpiexec, "-n", str(np_), args.driver, "-malloc_dump"]
        rc, out, timed_out = run(launch + ["-input_list", listing], env, args.timeout * len(files))
        # A dirty batch (crash, hang, report, leak): each file again on its own to find which.
        alone = report(out, timed_out, rc) is not None
        for path, ext, data in files:
            cmd = launch + ["-input", path]
            if alone:
                rc, out, timed_out = run(cmd, env, args.timeout)
                c = report(out, timed_out, rc) or classify_file(path, out)
            else:
                c = classify_file(path, out)
            counts[c] += 1
            by_ranks[(c, np_)] += 1
            if c not in ("accepted", "rejected_located"):
                keep = os.path.join(args.out, c)
                os.makedirs(keep, exist_ok=True)
                shutil.copy(path, keep)
                log = out if alone else "\n".join(l for l in out.splitlines() if l.startswith(path + ":"))
                with open(os.path.join(keep, os.path.basename(path) + ".np%d.log" % np_), "w") as fh:
                    fh.write("$ %s\n(exit %d%s)\n%s\n" % (" ".join(cmd), rc, ", timed out" if timed_out else "", log))
                print("fuzz: %s (np %d): %s, kept in %s" % (os.path.basename(path), np_, c, keep), flush=True)
            elif c == "accepted" and len(pool) < 500:
                pool.append(data)  # accepted mutants seed further mutations
                seeds.append((ext, data))
            os.remove(path)
            n += 1
        if batches % 20 == 0:
            print("fuzz: %d runs: %s" % (n, dict(counts)), flush=True)
    classes = ["accepted", "rejected_located", "rejected_unlocated", "crash", "sanitizer", "leak", "hang"]
    lines = ["fuzz summary: %d runs in %g minutes (random seed %d)" % (n, args.minutes, seed)]
    for c in classes:
        lines.append("  %-19s %6d   (np 1: %d, np 2: %d)" % (c, counts[c], by_ranks[(c, 1)], by_ranks[(c, 2)]))
    text = "\n".join(lines)
    print(text)
    with open(os.path.join(args.out, "summary.txt"), "w") as fh:
        fh.write(text + "\n")
    bad = sum(counts[c] for c in classes[2:])
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
