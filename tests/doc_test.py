#!/usr/bin/env python3
"""Runs the shell code blocks of README.md and docs/*.md as written (python3 standard library only).

Convention (docs/development.md, "The documentation test"):
  ```sh / ```bash   every line is run; the blocks of one file run in order, in one fresh working
                    folder (each block its own bash with -e -o pipefail, so a variable lives in its block)
  ```console        only the lines that start with "$ " are run; the rest is output, not compared
  ```sh template    placeholders (VOLUME, your own paths): shown, never run
  ```sh setup       installs, builds or runs the test suite (scripts/setup.sh, cmake, fuzz.sh,
                    meshless-bench): runs as written from a checkout, but not inside this test
  ```python         a script of the Python module, run whole by the --python interpreter (with
                    --python-path first on its module path) in the same working folder; skipped
                    without --python
  a line ending in "# template" is a placeholder line inside a runnable block: skipped
Any other fence (```text, ```, ```cmake ...) is not shell and is not run, except that a ```text block
right after a line "<!-- help: ARGS -->" must equal the output of `meshless ARGS --help` (run in the
working folder); --update-help rewrites those blocks from the executable.

The working folder of each file is TMP/main, with TMP/shared a link to the real shared folder, so
"../shared/data/..." resolves as it does beside a checkout; `meshless` is on PATH (its folder first).
Outputs go under out/ in that folder. Every output name (-o, --png, --diff, and so on) must be
distinct across all the files. On a failure: the file, the line, the command and its output; exit 1.
Without the shared data: a skip message and exit 77 (ctest's SKIP_RETURN_CODE).

usage: doc_test.py --meshless PATH [--root REPO] [--shared DIR] [--sanitized] [--keep]
                   [--python PYTHON --python-path DIR] [FILE.md ...]
"""
import argparse
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

SHELL_INFOS = {"sh", "bash", "console"}
SKIP_ATTRS = {"template", "setup"}
OUTPUT_OPTIONS = {"-o", "--png", "--diff", "--markdown", "--work"}
FENCE = re.compile(r"^(\s*)(`{3,}|~{3,})\s*([^`]*)$")


class Block:
    def __init__(self, path, line, info):
        self.path, self.line, self.info = path, line, info
        self.commands = []  # (line number, text)
        self.raw = []  # the block's lines as written (```python blocks run them as one script)


def parse_blocks(path):
    """Every fenced block of a Markdown file, with its commands as (line, logical line) pairs."""
    blocks, block, fence = [], None, None
    pending, pending_line = None, 0
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    for n, raw in enumerate(lines, start=1):
        if block is None:
            m = FENCE.match(raw)
            if m:
                fence = m.group(2)
                block = Block(path, n, m.group(3).split())
            continue
        if raw.strip().startswith(fence[0] * 3) and raw.strip().strip(fence[0]) == "":
            blocks.append(block)
            block, pending = None, None
            continue
        block.raw.append(raw)
        text = raw
        if block.info and block.info[0] == "console":
            if pending is None:
                if not text.startswith("$ "):
                    continue
                text = text[2:]
        if pending is not None:
            text = pending + "\n" + text
        else:
            pending_line = n
        if text.endswith("\\"):
            pending = text
            continue
        pending = None
        if text.strip():
            block.commands.append((pending_line, text))
    return blocks


def runnable(block, with_python=False):
    attrs = set(block.info[1:]) if block.info else set()
    if block.info and block.info[0] == "python":
        return with_python and not (SKIP_ATTRS & attrs)
    return bool(block.info) and block.info[0] in SHELL_INFOS and not (SKIP_ATTRS & attrs)


def is_template(command):
    return re.search(r"#\s*template\s*$", command) is not None


def output_names(command):
    """The file names a command line writes through its output options (for the distinct-names check)."""
    try:
        words = shlex.split(command.replace("\\\n", " "), comments=True)
    except ValueError:
        return []
    names = []
    for i, w in enumerate(words):
        if w in OUTPUT_OPTIONS and i + 1 < len(words) and words[i + 1] != "-":
            names.append(words[i + 1])
        elif "=" in w and w.split("=", 1)[0] in OUTPUT_OPTIONS - {"-o"}:
            names.append(w.split("=", 1)[1])
    return names


HELP_MARK = re.compile(r"^<!-- help: (.*) -->$")


def check_help(path, rel, args, env, cwd):
    """Compares (or, with --update-help, rewrites) the help blocks of a file; returns the failures."""
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    failures, out, i = 0, [], 0
    while i < len(lines):
        out.append(lines[i])
        m = HELP_MARK.match(lines[i])
        if not m or i + 1 >= len(lines) or lines[i + 1].strip() != "```text":
            i += 1
            continue
        end = i + 2
        while end < len(lines) and lines[end].strip() != "```":
            end += 1
        r = subprocess.run(["bash", "-c", "meshless " + m.group(1) + " --help"], cwd=cwd, env=env,
                           capture_output=True, text=True, errors="replace")
        want = r.stdout.rstrip("\n").split("\n")
        have = lines[i + 2:end]
        if args.update_help:
            out += ["```text"] + want + ["```"]
        elif r.returncode != 0 or want != have:
            failures += 1
            print(f"FAIL {rel}:{i + 1}: the help block differs from `meshless {m.group(1)} --help` "
                  f"(exit {r.returncode}; tests/doc_test.py --update-help rewrites it)")
        else:
            print(f"ok   {rel}:{i + 1} (help of {m.group(1)})")
        if not args.update_help:
            out += lines[i + 1:end + 1]
        i = end + 1
    if args.update_help:
        with open(path, "w", encoding="utf-8") as f:
            f.write("\n".join(out))
    return failures


def run_file(path, blocks, args, rel):
    tmp = tempfile.mkdtemp(prefix="meshless-doc-")
    work = os.path.join(tmp, "main")
    os.mkdir(work)
    os.symlink(os.path.abspath(args.shared), os.path.join(tmp, "shared"))
    env = dict(os.environ)
    env["PATH"] = os.path.dirname(os.path.abspath(args.meshless)) + os.pathsep + env.get("PATH", "")
    if args.python:  # the ```python blocks: the module's interpreter, the build's package first
        env["PYTHONPATH"] = os.path.abspath(args.python_path) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    env.pop("MESHLESS_PROGRESS", None)
    failures = 0
    try:
        failures += check_help(path, rel, args, env, work)
        for b in blocks:
            lines = [(n, c) for n, c in b.commands if not is_template(c)]
            if not lines:
                continue
            script = ["set -e -o pipefail", "trap 'echo \"@@doc-test-line $__doc_line $?\" >&2' EXIT"]
            for n, c in lines:
                script.append(f"__doc_line={n}")
                script.append(c)
            script.append("__doc_line=0")
            command = ["bash", "-c", "\n".join(script)]
            if b.info[0] == "python":
                command = [args.python, "-c", "\n".join(b.raw)]
            benv = dict(env)
            if args.sanitized and "mpirun" in "\n".join(c for _, c in lines):
                # as tests/cli/test_ooc_pipeline.cpp: libmpi's own allocations are not ours to report
                benv["LSAN_OPTIONS"] = "detect_leaks=0"
            t0 = time.monotonic()
            try:
                r = subprocess.run(command, cwd=work, env=benv, stdin=subprocess.DEVNULL,
                                   capture_output=True, text=True, errors="replace", timeout=args.timeout)
                out, err, code = r.stdout, r.stderr, r.returncode
            except subprocess.TimeoutExpired as e:
                out = e.stdout.decode(errors="replace") if isinstance(e.stdout, bytes) else (e.stdout or "")
                err = e.stderr.decode(errors="replace") if isinstance(e.stderr, bytes) else (e.stderr or "")
                code = -1
                err += f"\n(timed out after {args.timeout} s)"
            secs = time.monotonic() - t0
            marks = re.findall(r"@@doc-test-line (\d+) (-?\d+)", err)
            err = re.sub(r"@@doc-test-line \d+ -?\d+\n?", "", err)
            failed_line = int(marks[-1][0]) if marks else 0
            if code == 0:
                print(f"ok   {rel}:{b.line} ({len(lines)} commands, {secs:.1f} s)")
                continue
            failures += 1
            line = failed_line or b.line
            command = next((c for n, c in lines if n == line), "?")
            print(f"FAIL {rel}:{line}: exit {code} after {secs:.1f} s\n  $ {command}")
            tail = (out + err).strip().splitlines()[-20:]
            for t in tail:
                print("  | " + t)
    finally:
        if args.keep:
            print(f"     (kept {work})")
        else:
            shutil.rmtree(tmp, ignore_errors=True)
    return failures


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    here = os.path.dirname(os.path.abspath(__file__))
    p.add_argument("--meshless", required=True, help="the built meshless executable")
    p.add_argument("--root", default=os.path.dirname(here), help="the repository (default: this file's ..)")
    p.add_argument("--shared", help="the shared folder (default: ROOT/../shared)")
    p.add_argument("--sanitized", action="store_true", help="the executable has ASan: no leak reports from mpirun")
    p.add_argument("--timeout", type=int, default=300, help="seconds per block (default 300)")
    p.add_argument("--keep", action="store_true", help="keep the working folders")
    p.add_argument("--python", help="the interpreter of the Python module: run the ```python blocks with it")
    p.add_argument("--python-path", help="with --python: the folder that holds the built package meshless/")
    p.add_argument("--update-help", action="store_true", help="rewrite the help blocks from the executable")
    p.add_argument("--list", action="store_true", help="print the commands that would run, run nothing")
    p.add_argument("files", nargs="*", help="Markdown files (default: README.md and docs/*.md)")
    args = p.parse_args()
    root = os.path.abspath(args.root)
    args.shared = args.shared or os.path.join(os.path.dirname(root), "shared")
    files = args.files or [os.path.join(root, "README.md")] + sorted(
        os.path.join(root, "docs", f) for f in os.listdir(os.path.join(root, "docs")) if f.endswith(".md"))

    parsed, seen, failures = [], {}, 0
    for path in files:
        rel = os.path.relpath(path, root)
        blocks = [b for b in parse_blocks(path) if runnable(b, bool(args.python))]
        parsed.append((path, rel, blocks))
        for b in blocks:
            for n, c in b.commands:
                if is_template(c):
                    continue
                for name in output_names(c):
                    if name in seen:
                        print(f"FAIL {rel}:{n}: output '{name}' is also written at {seen[name]}")
                        failures += 1
                    else:
                        seen[name] = f"{rel}:{n}"
    if args.list:
        for path, rel, blocks in parsed:
            for b in blocks:
                for n, c in b.commands:
                    print(f"{rel}:{n}: {'(template) ' if is_template(c) else ''}{c}")
        return 0
    if not os.path.isfile(args.meshless):
        print(f"doc_test: no executable at {args.meshless}")
        return 1
    if not os.path.isdir(os.path.join(args.shared, "data")):
        print(f"SKIP: {os.path.join(args.shared, 'data')} not found (the documentation's commands read it)")
        return 77
    t0 = time.monotonic()
    for path, rel, blocks in parsed:
        failures += run_file(path, blocks, args, rel)
    total = sum(len(b.commands) for _, _, bs in parsed for b in bs)
    print(f"{total} command lines in {sum(len(bs) for _, _, bs in parsed)} blocks of {len(parsed)} files, "
          f"{time.monotonic() - t0:.1f} s: {'all ran' if failures == 0 else f'{failures} failed'}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
