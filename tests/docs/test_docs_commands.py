"""Every shell command of README.md and docs/*.md runs as a reader would type it.

The commands are the lines of ```sh blocks and the indented command lines of the text. Each runs
from a scratch folder laid out like the repository (scenes/, tests/data/ and examples/ linked in,
everything else, docs/ included, a fresh folder there, so that outputs such as `-o
docs/benchmarks` land in the scratch folder), with `tumble` and `build/release/apps/tumble` the
tumble of this build. What a reader would have to supply is supplied (PLACEHOLDERS below), and a
command that would take minutes gets a smaller budget through options of its own (BUDGET), added
only where the command does not set them. Commands that install, build or run the whole test
suite are not run again inside the suite: their scripts and the files they name must exist and
parse (`bash -n`); tests/install/install_test.sh runs the install and the examples' build. Python
scripts named after mpirun must exist and compile (python/tests and tests/mpi run them), and so
must a test binary a line names, where this build has it.

A command fails the test if it exits non-zero, or if it names a repository file that does not
exist. Synopsis lines (`tumble render SCENE.yaml [-o out.mp4] ...`) are checked option by option
against the command's --help.
"""
import os
import re
import shlex
import shutil
import subprocess
from pathlib import Path

import pytest

SOURCE = Path(os.environ["TUMBLE_SOURCE_DIR"])
CLI = Path(os.environ["TUMBLE_CLI"])
BUILD = CLI.parent.parent  # build/<dir>/apps/tumble

VERBS = {"run", "validate", "ccd", "compare", "report", "bench", "bench-batch", "sim2real",
         "sweep", "render", "query", "--help", "--version"}

# Names a reader replaces with their own files.
PLACEHOLDERS = {
    "my_scene.yaml": "scenes/bounce.yaml",
    "my_queries.yaml": "my_queries.yaml",  # written from docs/scene-format.md's example
    "study.yaml": "scenes/sweeps/stack10_study.yaml",
    "tests/data/external/ccd-sample-queries/<file>.csv":
        "tests/data/external/ccd-sample-queries/erleben-spikes/vertex-face/data_0_0.csv",
}

# Options that bound a command's work, each added where the command does not set it.
BUDGET = {
    "run": [("--steps", "3", ("--steps", "--duration"))],
    "render": [("--duration", "0.05", ("--duration",)), ("--size", "160x120", ("--size",))],
    "compare": [("--steps", "10", ("--steps",))],
    "bench": [("--steps", "2", ("--steps",)), ("--repetitions", "1", ("--repetitions",))],
    "bench-batch": [("--worlds", "1", ("--worlds",)), ("--threads", "1", ("--threads",)),
                    ("--steps", "2", ("--steps",)), ("--repetitions", "1", ("--repetitions",))],
    "sim2real": [("--worlds", "2", ("--worlds",)), ("--steps", "5", ("--steps",))],
}


def documents():
    return [SOURCE / "README.md"] + sorted((SOURCE / "docs").glob("*.md"))


def is_command_line(words):
    """An indented line of text that is a command: tumble and a word that may be a verb (known or
    misspelt: "tumble 196 ns" in a table of output is not), or a script, or mpirun."""
    if not words:
        return False
    if words[0] in ("tumble", "build/release/apps/tumble"):
        return len(words) > 1 and re.match(r"^(--)?[a-z][a-z-]*$", words[1]) is not None
    return words[0] in ("mpirun", "srun", "bash") or words[0].startswith("scripts/")


def commands():
    """(document, line, command) for every command line, continuation lines joined."""
    found = []
    for doc in documents():
        fence = None
        pending = None
        for number, line in enumerate(doc.read_text().splitlines(), start=1):
            if line.startswith("```"):
                fence = None if fence is not None else line[3:].strip()
                continue
            if fence in ("sh", "bash", "shell", "console"):
                text = line.strip()
            elif fence is None and line.startswith("    "):
                text = line.strip()
                try:
                    words = shlex.split(text, comments=True)
                except ValueError:
                    continue
                if pending is None and not is_command_line(words):
                    continue
            else:
                continue
            if pending is None and text.startswith("[") and found and found[-1][0] == doc.name:
                # A synopsis's options wrapped onto the next line.
                found[-1] = (found[-1][0], found[-1][1], found[-1][2] + " " + text)
                continue
            if pending is not None:
                pending = (pending[0], pending[1], pending[2] + " " + text)
            elif text and not text.startswith("#"):
                pending = (doc.name, number, text)
            if pending is not None and not pending[2].endswith("\\"):
                found.append(pending)
                pending = None
            elif pending is not None:
                pending = (pending[0], pending[1], pending[2][:-1])
    return found


def query_example():
    text = (SOURCE / "docs" / "scene-format.md").read_text()
    start = text.index("\nqueries:\n") + 1
    return text[start:text.index("```", start)]


@pytest.fixture
def scratch(tmp_path):
    """A fresh folder for each command: one's outputs are not another's (a sweep resumes the runs
    it finds complete in its output folder, and would then run nothing)."""
    root = tmp_path
    (root / "tests").mkdir()
    for link, target in (("scenes", "scenes"), ("examples", "examples"), ("scripts", "scripts"),
                         ("tests/data", "tests/data")):
        (root / link).symlink_to(SOURCE / target)
    # The query example's mesh, beside it (a link would lead out of its folder, which tumble
    # refuses).
    shutil.copytree(SOURCE / "scenes" / "meshes", root / "meshes")
    (root / "docs").mkdir()
    (root / "my_queries.yaml").write_text(query_example())
    bin_dir = root / "bin"
    bin_dir.mkdir()
    (bin_dir / "tumble").symlink_to(CLI)
    (root / "build" / "release" / "apps").mkdir(parents=True)
    (root / "build" / "release" / "apps" / "tumble").symlink_to(CLI)
    (root / "build" / "release" / "python").symlink_to(BUILD / "python")
    return root


def tumble_verbs():
    out = subprocess.run([CLI, "--help"], capture_output=True, text=True, check=True).stdout
    return set(re.findall(r"^  (\S+)\s", out.split("Subcommands:")[1], re.M))


def run_tumble(words, root, env):
    """A tumble command with its placeholders filled in and its budget added."""
    verb = words[1] if len(words) > 1 else ""
    assert verb in ("--help", "--version") or verb in tumble_verbs(), f"no verb 'tumble {verb}'"
    words = [PLACEHOLDERS.get(w, w) for w in words]
    # The shell's globbing, from the scratch folder.
    expanded = []
    for w in words:
        matches = sorted(str(p.relative_to(root)) for p in root.glob(w)) if "*" in w else []
        expanded += matches or [w]  # as the shell does: no match, the word itself
    words = expanded
    # Outputs given as absolute paths (a cluster's /scratch) go under the scratch folder.
    for i in range(len(words) - 1):
        if words[i] in ("-o", "--output") and words[i + 1].startswith("/"):
            words[i + 1] = str(root / words[i + 1].lstrip("/"))
    for option, value, unless in BUDGET.get(verb, []):
        if not any(w in unless for w in words):
            words += [option, value]
    words[0] = str(CLI)
    result = subprocess.run(words, cwd=root, env=env, capture_output=True, text=True,
                            timeout=600)
    assert result.returncode == 0, f"{' '.join(words)}\n{result.stdout}\n{result.stderr}"


def check_synopsis(words):
    """`tumble VERB SCENE [-o out] ...`: every option it shows is one of the verb's."""
    verb = words[1]
    help_text = subprocess.run([CLI, verb, "--help"], capture_output=True, text=True,
                               check=True).stdout
    for option in re.findall(r"\[(-{1,2}[a-z-]+)", " ".join(words)):
        assert re.search(rf"(^|[ ,]){re.escape(option)}\b", help_text, re.M), \
            f"tumble {verb} has no {option}"


def check_files(words):
    """The repository paths a build or install command names exist (a folder alone too)."""
    checked = 0
    for w in words:
        for part in re.split(r"[=:]", w):
            if re.match(r"^(examples|scripts|tests|scenes|docs|python)(/|$)", part):
                assert (SOURCE / part).exists(), f"{part} does not exist"
                checked += 1
    return checked


DOCUMENTED = commands()


def test_the_documents_have_commands():
    # README's run, render and sweep lines among them: the extraction finds what is there.
    texts = [c for _, _, c in DOCUMENTED]
    assert any("tumble run scenes/bounce.yaml" in c for c in texts)
    assert any(c.startswith("bash scripts/test.sh") for c in texts)
    assert len(DOCUMENTED) >= 30


@pytest.mark.parametrize("document,line,command", DOCUMENTED,
                         ids=[f"{d}:{n}" for d, n, _ in DOCUMENTED])
def test_documented_command_runs(document, line, command, scratch):
    env = dict(os.environ)
    env["PATH"] = f"{scratch / 'bin'}:{env['PATH']}"
    env["OMPI_ALLOW_RUN_AS_ROOT"] = "1"
    env["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] = "1"
    words = shlex.split(command, comments=True)
    # Environment assignments in front of the command.
    while words and re.match(r"^[A-Z_][A-Z0-9_]*=", words[0]):
        name, value = words.pop(0).split("=", 1)
        env[name] = value
    # mpirun or srun and their options: the command they start is run here in one process
    # (tests/mpi runs the sweeps over ranks).
    if words and words[0] in ("mpirun", "srun"):
        words.pop(0)
        while words and words[0].startswith("-"):
            flag = words.pop(0)
            if flag in ("-n", "-np", "--hostfile", "-hostfile", "--host"):
                words.pop(0)
    assert words, f"{document}:{line}: an empty command"
    program = words[0]
    if program in ("tumble", "build/release/apps/tumble"):
        if any(w.startswith("[") for w in words):
            check_synopsis(words)
        else:
            run_tumble(words, scratch, env)
    elif program == "bash" and words[1].startswith("scripts/"):
        script = SOURCE / words[1]
        assert script.is_file(), f"{words[1]} does not exist"
        subprocess.run(["bash", "-n", script], check=True)
    elif program == "python3" and "-c" in words:
        if not (BUILD / "python" / "tumble").is_dir():
            pytest.skip("this build has no Python module (the sanitizer build leaves it out)")
        result = subprocess.run(words, cwd=scratch, env=env, capture_output=True, text=True,
                                timeout=120)
        assert result.returncode == 0, result.stderr
    elif program == "python3":
        # A script of examples/python (under mpirun in the docs): it must exist and compile; its
        # runs are in python/tests and tests/mpi.
        script = SOURCE / words[1]
        assert script.is_file(), f"{words[1]} does not exist"
        subprocess.run(["python3", "-m", "py_compile", script], check=True)
    elif "/tests/" in program:
        # A test binary of a build folder (build-dev/tests/test_render): a target of this build.
        name = program.split("/tests/", 1)[1]
        if not (BUILD / "tests" / name).exists():
            pytest.skip(f"this build has no {name} (a part it leaves out)")
    elif program.startswith("build-examples/"):
        # A program of examples/, built by the line before it (tests/install builds them all).
        name = program.split("/", 1)[1]
        assert (SOURCE / "examples" / f"{name}.cpp").is_file(), f"no examples/{name}.cpp"
    elif program == "export":
        assert re.match(r"^[A-Z_]+=", words[1]), command
    elif program in ("cmake", "ctest", "g++"):
        # Each names a folder or file of the repository (examples, ., a source) or the build.
        assert check_files(words) > 0 or any(w in (".", "build/release") or
                                             w.startswith("build/") for w in words), command
    else:
        pytest.fail(f"{document}:{line}: no rule for '{program}'")
