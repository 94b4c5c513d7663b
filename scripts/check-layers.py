#!/usr/bin/env python3
"""The layers of lptn, checked on every #include of the tree (a ctest test, tests/layers).

Each directory below is one module; DEPENDS lists what each may include directly, and a module
may include everything its dependencies may (the closure). An include fails the check when
  - it reaches a module outside that closure (a layer crossed the wrong way: firmware/ into
    trainer/, trainer/ into tools/, a tool into the command line...);
  - it names another module's internal/ header (internal headers stay inside their module; the
    tests of a module listed in INTERNAL_FOR_TESTS may reach its internals, as tests beside the
    code do);
  - it is a bare name that only some other module's include directory resolves ("replay.hpp"
    for firmware/linux/replay.hpp): every include is relative to the including file or to a
    module root (the repository root, common/, firmware/include/, tests/support/ (the test-support
    library, lptn_test_support), or the generated headers).

  scripts/check-layers.py [REPO]    exit 0 if every include keeps to the layers; else one line each
"""
import os
import re
import subprocess
import sys

# Longest prefix first wins. The generated headers (lptn/can/*, lptn/bus/*, lptn/version.hpp) belong to the
# modules whose build generates them (can/codecs: its CMakeLists.txt runs can/codegen's programs).
MODULES = [
    "common", "can/codecs", "hostio",
    "firmware/include", "firmware/linux", "firmware/baremetal", "firmware/calibration", "firmware/bench",
    "trainer/data", "trainer/model", "trainer/calibrate", "trainer/lm", "trainer/td3", "trainer/search", "trainer/diagnose",
    "trainer/fleet", "trainer/check", "trainer/workflow",
    "simulator/plant", "simulator/generate",
    "can/frames", "can/dbc", "can/bus", "can/codegen", "can/canfile", "can/canlog",
    "tools/export", "tools/replay", "tools/report",
    "programs/cli", "programs/vcan-bench",
    "tests",
]

# Direct dependencies: the layers, bottom up. common/, the CAN codecs and hostio/ know nothing of
# each other; firmware/ and trainer/ stand on them and never on each other; the CAN wing's host
# side (can/: DBC and bus map at run time, log formats, conversion) beside trainer/; tools/ on top.
DEPENDS = {
    "common": [],
    "can/codecs": [],
    "hostio": [],
    "firmware/include": ["common", "can/codecs"],
    "firmware/calibration": ["common"],
    # The log readers' interface and candump's reader: the daemon's replay and the host's log formats.
    "can/frames": ["firmware/include", "hostio"],
    "firmware/linux": ["firmware/include", "can/frames", "hostio"],
    "firmware/baremetal": ["firmware/include", "firmware/calibration"],
    # Benchmarks are tests beside the code: they may use the test-support library's simulated converter.
    "firmware/bench": ["firmware/linux", "firmware/calibration", "tests"],
    "trainer/data": ["common", "hostio"],
    "trainer/model": ["trainer/data"],
    "trainer/calibrate": ["trainer/model"],
    # LM (Ceres) sits above what every calibrator shares, so that reading a calibration needs no Ceres.
    "trainer/lm": ["trainer/calibrate"],
    "trainer/td3": ["trainer/calibrate"],
    # Random search and CMA-ES: the baselines that show what TD3's learning adds (no libtorch).
    "trainer/search": ["trainer/calibrate"],
    "trainer/diagnose": ["trainer/lm"],
    "trainer/fleet": ["trainer/lm"],
    # Does a calibration still hold on new data: diagnose's adequacy and the fleet's cooling factor.
    "trainer/check": ["trainer/diagnose", "trainer/fleet"],
    # Request to result: a calibration as every program runs it (TD3 given by the one that links it).
    "trainer/workflow": ["trainer/search", "trainer/fleet", "trainer/check"],
    "simulator/plant": ["common"],
    "simulator/generate": ["simulator/plant", "trainer/model"],
    "can/dbc": ["hostio"],
    # A bus map read at run time: the firmware's decoder interface over a DBC read at run time.
    "can/bus": ["firmware/include", "can/dbc"],
    # The build's generators of the codecs and the bus glue (can/codecs' headers), programs for the
    # build host built from the two readers: the readers are the one description of the CAN bus.
    "can/codegen": ["can/dbc", "can/bus", "hostio"],
    "can/canfile": ["can/frames"],
    "can/canlog": ["trainer/data", "can/canfile", "can/bus"],
    "tools/export": ["trainer/calibrate"],
    "tools/replay": ["trainer/calibrate", "can/canfile", "firmware/linux", "firmware/calibration"],
    "tools/report": ["trainer/diagnose", "trainer/fleet", "trainer/check"],
    "programs/cli": ["simulator/generate", "tools/export", "can/bus", "can/canfile", "can/canlog", "tools/replay",
                  "tools/report", "trainer/td3", "trainer/workflow"],
    "programs/vcan-bench": ["tools/replay", "can/bus"],
    "tests": [m for m in MODULES if m not in ("tests", "firmware/bench")],
}

# Internal headers the tests of a module may reach (its own tests, beside the code).
INTERNAL_FOR_TESTS = {"common", "trainer/diagnose", "trainer/data", "trainer/td3", "trainer/search",
                      "trainer/fleet", "can/canfile", "hostio"}

# Module roots a quoted include may be relative to, and headers generated into the build tree.
ROOTS = ["", "common", "firmware/include", "tests/support"]
# thermal_calibration.hpp: headers the tests export at build time.
GENERATED = {"lptn/version.hpp": "common", "lptn/can/": "can/codecs", "lptn/bus/": "can/codecs", "thermal_calibration.hpp": "tests"}
SOURCE_EXTENSIONS = (".hpp", ".cpp", ".h", ".cc")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def module_of(path):
    """The module a path belongs to: the longest module directory it is in."""
    for m in sorted(MODULES, key=len, reverse=True):
        if path == m or path.startswith(m + "/"):
            return m
    return None


def closure(module):
    seen, todo = set(), [module]
    while todo:
        m = todo.pop()
        for d in DEPENDS[m]:
            if d not in seen:
                seen.add(d)
                todo.append(d)
    return seen


def resolve(repo, including, name):
    """The repository path an include names, or None where only another module's include
    directory could resolve it. Generated headers resolve to their module's pseudo-path."""
    here = os.path.dirname(including)
    candidate = os.path.normpath(os.path.join(here, name))
    if os.path.isfile(os.path.join(repo, candidate)):
        return candidate
    for root in ROOTS:
        candidate = os.path.normpath(os.path.join(root, name))
        if os.path.isfile(os.path.join(repo, candidate)):
            return candidate
    for prefix, module in GENERATED.items():
        if name == prefix or (prefix.endswith("/") and name.startswith(prefix)):
            return module + "/(generated)/" + name
    return None


def files(repo):
    for top in MODULES:
        base = os.path.join(repo, top)
        if not os.path.isdir(base):
            continue
        for dirpath, dirnames, filenames in os.walk(base):
            dirnames[:] = [d for d in dirnames if d not in ("corpus", "build")]
            for f in filenames:
                if f.endswith(SOURCE_EXTENSIONS):
                    yield os.path.relpath(os.path.join(dirpath, f), repo)


def check(repo):
    problems = []
    counted = 0
    for path in sorted(files(repo)):
        module = module_of(path)
        allowed = closure(module) | {module}
        with open(os.path.join(repo, path), encoding="utf-8", errors="replace") as f:
            for number, line in enumerate(f, 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                counted += 1
                name = m.group(1)
                target = resolve(repo, path, name)
                where = f"{path}:{number}"
                if target is None:
                    problems.append(f"{where}: \"{name}\" is not relative to this file or a module root "
                                    "(write the path from the repository root)")
                    continue
                to = module_of(target)
                if to is None:
                    problems.append(f"{where}: \"{name}\" is outside every module")
                    continue
                if to not in allowed:
                    problems.append(f"{where}: {module} includes {target} of {to}, which is not below it "
                                    f"(it may include: {', '.join(sorted(allowed))})")
                if "/internal/" in "/" + target and to != module and not (module == "tests" and to in INTERNAL_FOR_TESTS):
                    problems.append(f"{where}: {target} is internal to {to}")
    return problems, counted


def self_test():
    """The check must fail where it should: a small tree with one include of each kind it refuses
    (and one it allows), each reported once."""
    import tempfile
    tree = {
        "common/lptn/model.hpp": "",
        "common/lptn/internal/lu.hpp": "",
        "trainer/data/dataset.hpp": '#include "lptn/model.hpp"\n',            # allowed: down a layer
        "trainer/data/internal/raw.hpp": "",
        "trainer/calibrate/problem.cpp": '#include "trainer/lm/lm.hpp"\n',  # LM above the shared part
        "trainer/lm/lm.hpp": '#include "trainer/calibrate/problem.hpp"\n',
        "trainer/calibrate/problem.hpp": "",
        "firmware/include/lptn/firmware/observer.hpp": '#include "trainer/data/dataset.hpp"\n',  # firmware into trainer
        "firmware/linux/replay.hpp": "",
        "tools/replay/run.cpp": '#include "replay.hpp"\n#include "programs/cli/commands.hpp"\n',  # bare; tool into cli
        "programs/cli/commands.hpp": "",
        "can/canlog/convert.cpp": '#include "trainer/data/internal/raw.hpp"\n',  # another module's internal
        "tests/data/t.cpp": '#include "trainer/data/internal/raw.hpp"\n',  # a module's tests: allowed
    }
    with tempfile.TemporaryDirectory() as d:
        for path, text in tree.items():
            os.makedirs(os.path.dirname(os.path.join(d, path)), exist_ok=True)
            with open(os.path.join(d, path), "w") as f:
                f.write(text)
        problems, _ = check(d)
    expected = ["trainer/calibrate/problem.cpp:1:", "firmware/include/lptn/firmware/observer.hpp:1:",
                "tools/replay/run.cpp:1:", "tools/replay/run.cpp:2:", "can/canlog/convert.cpp:1:"]
    found = sorted(p.split(" ")[0] for p in problems)
    if found != sorted(expected):
        print("check-layers self-test: expected problems at", sorted(expected), "got:")
        for p in problems:
            print("  " + p)
        return 1
    print(f"check-layers self-test: the {len(expected)} wrong-way includes of the test tree are refused, the rest allowed")
    return self_test_layout()


def self_test_layout():
    """The layout check on the real module list and a tree made for it: a table naming every module
    but trainer/lm and naming a directory the tree lacks, and a source file in no module."""
    import tempfile
    rows = [f"| `{m}/` | x |" for m in MODULES if m != "trainer/lm"] + ["| `trainer/gone/` | x |"]
    with tempfile.TemporaryDirectory() as d:
        os.makedirs(os.path.join(d, "docs"))
        with open(os.path.join(d, LAYOUT_DOC), "w") as f:
            f.write("\n".join(["# Layout", "", "| directory | what it holds |", "|---|---|"] + rows + ["", "more"]) + "\n")
        for m in MODULES:
            os.makedirs(os.path.join(d, m))
        os.makedirs(os.path.join(d, "trainer/stray"))
        open(os.path.join(d, "trainer/stray/stray.cpp"), "w").close()
        open(os.path.join(d, "tests/t.cpp"), "w").close()  # tests/ is a module: fine
        problems, _ = layout(d)
    expected = [f"{LAYOUT_DOC}:{len(rows) + 4}:", f"{LAYOUT_DOC}:", "trainer/stray/stray.cpp:"]
    found = [p.split(" ")[0] for p in problems]
    wanted = ["trainer/gone/", "module trainer/lm/", "in no module"]
    if sorted(found) != sorted(expected) or not all(any(w in p for p in problems) for w in wanted):
        print("check-layers self-test: expected the layout's three problems, got:")
        for p in problems:
            print("  " + p)
        return 1
    print("check-layers self-test: a layout that names a missing directory, leaves out a module, or a source in no module is refused")
    return 0


LAYOUT_DOC = "docs/architecture.md"
SKIP_DIRS = {"build", ".git", "corpus", "node_modules"}


def layout(repo):
    """The layout table of docs/architecture.md against the tree and the modules above: every
    directory it names exists, every module is named (itself or a directory inside it), and every
    source file of the tree outside tests/ lies in a module, so that none escapes this check."""
    named = set()
    in_table = False
    with open(os.path.join(repo, LAYOUT_DOC), encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if line.startswith("| directory |"):
                in_table = True
            elif in_table and not line.startswith("|"):
                break
            elif in_table and not line.startswith("|---"):
                for d in re.findall(r"`([^`]+)`", line.split("|")[1]):
                    named.add((d.rstrip("/"), number))
    problems = []
    for d, number in sorted(named):
        if not os.path.isdir(os.path.join(repo, d)):
            problems.append(f"{LAYOUT_DOC}:{number}: the layout names {d}/, which the tree does not have")
    dirs = {d for d, _ in named}
    for m in MODULES:
        if not any(d == m or d.startswith(m + "/") for d in dirs):
            problems.append(f"{LAYOUT_DOC}: the layout does not name the module {m}/")
    for path in tree_files(repo):
        if path.endswith(SOURCE_EXTENSIONS) and module_of(path) is None:
            problems.append(f"{path}: in no module of the layer check's table (MODULES)")
    return problems, len(dirs)


def tree_files(repo):
    """The tree's files outside tests/, relative to repo: in a git work tree those git would keep
    (tracked, or new and not ignored: the demo's output, demo-out/, is ignored, and a user runs the
    tests after the demo), elsewhere (a source archive) every file outside SKIP_DIRS."""
    try:
        listed = subprocess.run(["git", "-C", repo, "ls-files", "--cached", "--others", "--exclude-standard", "-z"],
                                capture_output=True, check=True).stdout.decode().split("\0")
        return sorted(p for p in listed if p and not p.startswith("tests/") and os.path.exists(os.path.join(repo, p)))
    except (OSError, subprocess.CalledProcessError):
        paths = []
        for dirpath, dirnames, filenames in os.walk(repo):
            dirnames[:] = sorted(d for d in dirnames if d not in SKIP_DIRS and not (dirpath == repo and d == "tests"))
            paths += [os.path.relpath(os.path.join(dirpath, f), repo) for f in sorted(filenames)]
        return paths


def main():
    if sys.argv[1:2] == ["--self-test"]:
        return self_test()
    if sys.argv[1:2] == ["--layout"]:
        repo = os.path.abspath(sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(__file__), ".."))
        problems, named = layout(repo)
        for p in problems:
            print(p)
        print(f"check-layers --layout: {named} directories in {LAYOUT_DOC}'s layout, {len(MODULES)} modules, "
              f"{len(problems)} problems")
        return 1 if problems else 0
    repo = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    problems, counted = check(repo)
    for p in problems:
        print(p)
    print(f"check-layers: {counted} includes in {len(MODULES)} modules, {len(problems)} crossing a layer the wrong way")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
