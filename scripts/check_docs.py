#!/usr/bin/env python3
"""Checks the project's Markdown pages against the tree, for the test suite (ctest: docs_check).

  scripts/check_docs.py [--root DIR] [--no-run] [--timeout S] [FILE.md ...]
  scripts/check_docs.py --self-test

Pages checked (unless FILEs are given): README.md, CHANGELOG.md, docs/**/*.md, perf/README.md and
python/README.md, those of them that exist. Prints one line per problem, `file:line: problem`, and
exits 1 when there is any:

  (a) a relative link or image (`[x](path)`, `[x](path#anchor)`, `[x]: path`, `<a href>`,
      `<img src>`) whose file does not exist, or whose `#anchor` names no heading of the .md file it
      points at (GitHub's slug rule: lower case, punctuation dropped, spaces to `-`, repeats -1, -2);
  (b) a repository path in backquotes (a word starting with one of the top-level folders below,
      optionally with a `:line`, `:name` or `#anchor` suffix; globs must match a file) that does
      not exist;
  (c) a fenced code block marked runnable (info string ```` ```sh run ````, ```` ```bash run ````
      or ```` ```python run ````) that does not exit 0: shell blocks run with
      `bash -e -o pipefail` from the repository root, Python blocks with /usr/bin/python3, each
      with a timeout (120 s). Only blocks marked `run` execute (--no-run skips them).

Standard library only.
"""
import argparse
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile
import urllib.parse

TOP_DIRS = ["accel", "api", "apps", "cmake", "docs", "engine", "include", "mpi", "perf", "python",
            "scripts", "simd", "stress", "tests", "view", "fuzz", ".ci"]
DEFAULT_PAGES = ["README.md", "CHANGELOG.md", "docs/**/*.md", "perf/README.md", "python/README.md"]
SHELLS = {"sh", "bash", "shell"}
PYTHONS = {"python", "python3", "py"}
PYTHON = "/usr/bin/python3"

FENCE = re.compile(r"^( {0,3})(`{3,}|~{3,})(.*)$")
ATX = re.compile(r"^ {0,3}(#{1,6})(?:[ \t]+(.*?))?(?:[ \t]+#+)?[ \t]*$")
SETEXT = re.compile(r"^ {0,3}(=+|-+)[ \t]*$")
INLINE_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]\(\s*(<[^>]*>|[^\s()]*(?:\([^\s()]*\)[^\s()]*)*)"
                         r"(?:\s+(?:\"[^\"]*\"|'[^']*'|\([^)]*\)))?\s*\)")
REF_DEF = re.compile(r"^ {0,3}\[[^\]]+\]:\s*(<[^>]*>|\S+)")
HTML_ATTR = re.compile(r"<(?:a|img)\b[^>]*?\b(?:href|src)\s*=\s*(\"[^\"]*\"|'[^']*')", re.I)
HTML_ID = re.compile(r"<[a-z][^>]*?\b(?:id|name)\s*=\s*(\"[^\"]*\"|'[^']*')", re.I)
PATH_WORD = re.compile(r"^(?:\./)?(?:" + "|".join(re.escape(d) for d in TOP_DIRS) + r")/")
SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")


# ---------------------------------------------------------------------------------------------
# Markdown reading

def code_spans(line):
    """(start, end, content) of each inline code span on one line (CommonMark backtick runs)."""
    spans, i, n = [], 0, len(line)
    while i < n:
        if line[i] != "`":
            i += 1
            continue
        j = i
        while j < n and line[j] == "`":
            j += 1
        run = j - i
        k = j
        while True:
            k = line.find("`" * run, k)
            if k < 0:
                break
            if (k + run < n and line[k + run] == "`") or line[k - 1] == "`":
                k += 1
                while k < n and line[k] == "`":
                    k += 1
                continue
            break
        if k < 0:
            i = j
            continue
        content = line[j:k]
        if content.startswith(" ") and content.endswith(" ") and content.strip():
            content = content[1:-1]
        spans.append((i, k + run, content))
        i = k + run
    return spans


def blank_code(line):
    """The line with every code span replaced by same-length filler (links inside are not links)."""
    out = line
    for s, e, _ in code_spans(line):
        out = out[:s] + "x" * (e - s) + out[e:]
    return out


def scan(text):
    """Yields ('text', lineno, line) outside fences and ('block', lineno, info, body) per fence."""
    lines = text.split("\n")
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if m and not (m.group(2)[0] == "`" and "`" in m.group(3)):
            fence, info, start = m.group(2), m.group(3).strip(), i
            body = []
            i += 1
            while i < len(lines):
                c = re.match(r"^ {0,3}(" + re.escape(fence[0]) + r"{%d,})[ \t]*$" % len(fence), lines[i])
                if c:
                    break
                body.append(lines[i])
                i += 1
            yield ("block", start + 1, info, "\n".join(body) + "\n")
            i += 1
            continue
        yield ("text", i + 1, lines[i])
        i += 1


def heading_text_to_slug(text):
    """GitHub's anchor for a heading's text (as rendered: markup dropped, then the slug rule)."""
    t = text
    t = re.sub(r"!?\[((?:[^\[\]]|\[[^\[\]]*\])*)\]\([^)]*\)", r"\1", t)   # links, images -> text
    t = re.sub(r"<[^>]+>", "", t)                                         # HTML tags
    t = t.replace("`", "")
    t = re.sub(r"(?<![\w])_([^_]+)_(?![\w])", r"\1", t)                  # _emphasis_
    t = re.sub(r"(?<![\w])__([^_]+)__(?![\w])", r"\1", t)
    t = t.strip().lower()
    t = re.sub(r"[^\w\- ]", "", t)
    return t.replace(" ", "-")


def anchors_of(text):
    """Every anchor a page defines: heading slugs (with GitHub's -N for repeats) and HTML ids."""
    seen, out = {}, set()
    prev = None
    for item in scan(text):
        if item[0] != "text":
            prev = None
            continue
        line = item[2]
        heading = None
        m = ATX.match(line)
        if m:
            heading = m.group(2) or ""
        elif prev is not None and prev.strip() and SETEXT.match(line) and not FENCE.match(prev) \
                and not prev.lstrip().startswith(("|", "-", "*", ">")):
            heading = prev.strip()
        if heading is not None:
            base = heading_text_to_slug(heading)
            n = seen.get(base, 0)
            out.add(base if n == 0 else "%s-%d" % (base, n))
            seen[base] = n + 1
        for v in HTML_ID.findall(line):
            out.add(v[1:-1])
        prev = line
    return out


# ---------------------------------------------------------------------------------------------
# The checks

class Checker:
    def __init__(self, root, run_blocks=True, timeout=120.0):
        self.root = os.path.abspath(root)
        self.run_blocks = run_blocks
        self.timeout = timeout
        self.problems = []
        self._anchors = {}

    def problem(self, path, line, what):
        self.problems.append("%s:%d: %s" % (os.path.relpath(path, self.root), line, what))

    def anchors(self, path):
        if path not in self._anchors:
            with open(path, encoding="utf-8", errors="replace") as f:
                self._anchors[path] = anchors_of(f.read())
        return self._anchors[path]

    def check_target(self, page, line, target):
        if target.startswith("<") and target.endswith(">"):
            target = target[1:-1]
        if not target or SCHEME.match(target) or target.startswith("//"):
            return
        path_part, _, anchor = target.partition("#")
        path_part = urllib.parse.unquote(path_part)
        anchor = urllib.parse.unquote(anchor)
        if path_part == "":
            dest = page
        elif path_part.startswith("/"):
            dest = os.path.normpath(os.path.join(self.root, path_part.lstrip("/")))
        else:
            dest = os.path.normpath(os.path.join(os.path.dirname(page), path_part))
        if path_part.split("?")[0] != path_part:
            dest = dest.split("?")[0]
        if not os.path.exists(dest):
            self.problem(page, line, "broken link: %s (no such file)" % target)
            return
        if anchor and dest.endswith(".md") and os.path.isfile(dest):
            if anchor not in self.anchors(dest):
                self.problem(page, line, "broken link: %s (no heading #%s in %s)"
                             % (target, anchor, os.path.relpath(dest, self.root)))

    def check_path_word(self, page, line, word):
        word = word.strip(".,;()\"'")
        if not PATH_WORD.match(word) or "<" in word or ">" in word:
            return
        file_part = re.split(r"[:#]", word, maxsplit=1)[0]
        if not file_part:
            return
        candidates = [file_part]
        brace = re.search(r"\{([^{}]*)\}", file_part)
        if brace:
            candidates = [file_part[:brace.start()] + alt + file_part[brace.end():]
                          for alt in brace.group(1).split(",")]
        for c in candidates:
            full = os.path.join(self.root, c)
            if any(ch in c for ch in "*?["):
                if not glob.glob(full):
                    self.problem(page, line, "missing path: `%s` (matches no file)" % word)
                    return
            elif not os.path.exists(full):
                self.problem(page, line, "missing path: `%s`" % word)
                return

    def run_block(self, page, line, info, body):
        words = re.split(r"[\s,{}.]+", info)
        words = [w for w in words if w]
        if "run" not in words[1:]:
            return
        lang = words[0].lower()
        if lang in SHELLS:
            cmd = ["bash", "-e", "-o", "pipefail", "-c", body]
            stdin = None
        elif lang in PYTHONS:
            cmd = [PYTHON, "-"]
            stdin = body
        else:
            self.problem(page, line, "runnable block in unknown language '%s' (sh, bash, python)" % lang)
            return
        if not self.run_blocks:
            return
        try:
            r = subprocess.run(cmd, cwd=self.root, input=stdin, capture_output=True, text=True,
                               timeout=self.timeout)
        except subprocess.TimeoutExpired:
            self.problem(page, line, "runnable %s block timed out after %g s" % (lang, self.timeout))
            return
        except OSError as e:
            self.problem(page, line, "runnable %s block could not start: %s" % (lang, e))
            return
        if r.returncode != 0:
            tail = [l for l in (r.stderr or r.stdout or "").splitlines() if l.strip()]
            why = (": " + tail[-1].strip()[:200]) if tail else ""
            self.problem(page, line, "runnable %s block failed (exit %d)%s" % (lang, r.returncode, why))

    def check_page(self, page):
        with open(page, encoding="utf-8", errors="replace") as f:
            text = f.read()
        for item in scan(text):
            if item[0] == "block":
                _, line, info, body = item
                if info:
                    self.run_block(page, line, info, body)
                continue
            _, line, raw = item
            for _, _, content in code_spans(raw):
                for word in content.split():
                    self.check_path_word(page, line, word)
            plain = blank_code(raw)
            for m in INLINE_LINK.finditer(plain):
                self.check_target(page, line, m.group(1))
            m = REF_DEF.match(plain)
            if m:
                self.check_target(page, line, m.group(1))
            for v in HTML_ATTR.findall(plain):
                self.check_target(page, line, v[1:-1])

    def pages(self, files):
        if files:
            return [os.path.abspath(f) for f in files]
        out = []
        for pat in DEFAULT_PAGES:
            out += sorted(glob.glob(os.path.join(self.root, pat), recursive=True))
        return [p for p in out if os.path.isfile(p)]


def check(root, files=(), run_blocks=True, timeout=120.0):
    c = Checker(root, run_blocks, timeout)
    for page in c.pages(list(files)):
        c.check_page(page)
    return c.problems


# ---------------------------------------------------------------------------------------------
# Self-test: a small tree with one problem of each kind, then the same tree repaired

def self_test():
    failures = []

    def expect(cond, what):
        if not cond:
            failures.append(what)

    slugs = {
        "Use arbor from C++": "use-arbor-from-c",
        "From Python": "from-python",
        "`--accel auto`": "--accel-auto",
        "The columns: `err_brute` and [links](x.md)": "the-columns-err_brute-and-links",
        "Exit codes (1..127)": "exit-codes-1127",
    }
    for text, want in slugs.items():
        got = heading_text_to_slug(text)
        expect(got == want, "slug of %r: %r, want %r" % (text, got, want))
    a = anchors_of("# A\n## Same\ntext\n## Same\nSetext\n---\n```\n# not a heading\n```\n")
    expect(a == {"a", "same", "same-1", "setext"}, "anchors_of: %r" % sorted(a))

    made = []

    def tree(broken):
        d = tempfile.mkdtemp(prefix="check_docs_")
        made.append(d)
        for sub in ["docs", "scripts", "engine"]:
            os.makedirs(os.path.join(d, sub))
        open(os.path.join(d, "scripts", "tool.sh"), "w").write("#!/bin/sh\n")
        open(os.path.join(d, "engine", "mesh.h"), "w").write("\n")
        open(os.path.join(d, "docs", "guide.md"), "w").write(
            "# Guide\n\n## Use arbor from C++\n\ntext, `engine/mesh.h:12` and `scripts/tool.sh --x`\n"
            "[back](../README.md#start-here) [self](#guide)\n")
        link = "docs/gide.md" if broken else "docs/guide.md"
        anchor = "#use-arbor-from-python" if broken else "#use-arbor-from-c"
        path = "engine/mesh_missing.h" if broken else "engine/mesh.h"
        glob_path = "scripts/*.py" if broken else "scripts/*.sh"
        status = "exit 3" if broken else "true"
        py = "raise SystemExit(2)" if broken else "import os; assert os.path.isdir('docs')"
        open(os.path.join(d, "README.md"), "w").write(
            "# Start here\n\n"
            "See [the guide](%s), [its C++ part](docs/guide.md%s), ![pic](docs/guide.md).\n\n"
            "The mesh is in `%s`; the tools are `%s`; `build/release/whatever` is not checked.\n\n"
            "```sh\nscripts/not_run.sh   # not marked: never executed\n```\n\n"
            "```sh run\ntest -f scripts/tool.sh\n%s\n```\n\n"
            "```python run\n%s\n```\n\n"
            "A code span is not a link: `[x](nowhere.md)`.\n\n[ref]: docs/guide.md\n"
            % (link, anchor, path, glob_path, status, py))
        return d

    bad = check(tree(True))
    want = ["README.md:3: broken link: docs/gide.md",
            "README.md:3: broken link: docs/guide.md#use-arbor-from-python (no heading",
            "README.md:5: missing path: `engine/mesh_missing.h`",
            "README.md:5: missing path: `scripts/*.py` (matches no file)",
            "README.md:11: runnable sh block failed (exit 3)",
            "README.md:16: runnable python block failed (exit 2)"]
    for w in want:
        expect(any(p.startswith(w) for p in bad), "not caught: %s (got %r)" % (w, bad))
    expect(len(bad) == len(want), "expected %d problems, got %d: %r" % (len(want), len(bad), bad))
    good = check(tree(False))
    expect(good == [], "the repaired tree has problems: %r" % good)
    skipped = check(tree(True), run_blocks=False)
    expect(len(skipped) == len(want) - 2, "--no-run still ran blocks: %r" % skipped)

    for d in made:
        shutil.rmtree(d, ignore_errors=True)
    for f in failures:
        print("self-test: " + f)
    print("check_docs self-test: %s" % ("FAILED" if failures else "passed"))
    return 1 if failures else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("files", nargs="*", help="pages to check (default: the project's pages)")
    ap.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    ap.add_argument("--no-run", action="store_true", help="do not execute the blocks marked run")
    ap.add_argument("--timeout", type=float, default=120.0, help="seconds per runnable block")
    ap.add_argument("--self-test", action="store_true")
    a = ap.parse_args()
    if a.self_test:
        return self_test()
    problems = check(a.root, a.files, not a.no_run, a.timeout)
    for p in problems:
        print(p)
    if problems:
        print("check_docs: %d problem(s)" % len(problems), file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
