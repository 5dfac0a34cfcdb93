#!/usr/bin/python3
"""docs-check.py - every number a page quotes from sunmc's output is checked
(issue 41).

    scripts/docs-check.py [--slow] [PAGE.md ...]   (default: README.md docs/*.md)

A page marks what it quotes with an HTML comment before the text that quotes
it (invisible when the page is rendered):

    <!-- check: build/sunmc run docs/examples/my_dss.ini --units 1000 --out runs/my
    tol 1%
    13.17 @ ^total +0:25 +\\| #5
    91.25 @ centroid_noise
    -->

- the first line is the command, as the page shows it (it must appear on
  the page outside comments: the reader can run it) with its fixed seed
  (the config's or --seed); `check: same` reuses the output of the block
  before it on the page;
- `tol X%` (relative to the printed number) or `tol X` (absolute, in the
  units printed) is the tolerance of the block; a value line may end in its
  own `tol ...`;
- `and CMD` lines run further commands of the page after the first (each
  on the page), their output appended;
- each value line `VALUE @ REGEX [#K]` names a number as the page writes it
  (it must appear in the text after the comment, up to the next check
  comment or heading, once for each value line that names it) and where
  the command prints it: the K-th number (default 1) after the first match
  of REGEX (Python syntax, multi-line) in what the command wrote, stdout
  then stderr.

A number whose command takes minutes is marked `<!-- check-slow: ... -->`,
the same syntax: its command runs only with --slow (`make docs-check-slow`,
which runs only these) or DOCS_CHECK_SLOW=1 (both kinds); otherwise its
text is still held to the mark (the command on the page, each value quoted)
and the summary counts it as not run.  A number the machine decides (a
timing) is marked `<!-- machine: WHY -->` and is not checked;
`<!-- unchecked: WHY -->` is counted and not checked (for numbers of data
that are not committed: psd.md's public data).  The commands run in a temporary folder whose entries
link to the repository's (so `runs/...` is written there, never in your
tree), page by page, in page order; $SUNMC, when set, is the binary
`build/sunmc` names.  Exit 0 when every number is within its tolerance,
1 when one is not (each failure printed as PAGE:LINE: message), 2 on a
malformed mark.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

NUM = re.compile(r'[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?')
MARK = re.compile(r'<!--\s*(check-slow|check|machine|unchecked):(.*?)-->', re.S)
VALUE = re.compile(r'^(\S+)\s+@\s+(.*?)(?:\s+#(\d+))?(?:\s+tol\s+(\S+))?\s*$')
TIMEOUT_S = 300
SLOW_TIMEOUT_S = 3600  # the DSS's 8 px on-board budget takes 7 min of CPU, more on a loaded machine


class Malformed(Exception):
    pass


def parse_tol(text, where):
    m = re.fullmatch(r'(\d+(?:\.\d*)?)(%?)', text)
    if not m:
        raise Malformed(f"{where}: tolerance '{text}' is not a number or a percentage")
    return (float(m.group(1)) / 100.0, True) if m.group(2) else (float(m.group(1)), False)


def parse_block(body, where):
    lines = [l.strip() for l in body.strip().splitlines()]
    if not lines or not lines[0]:
        raise Malformed(f"{where}: check mark without a command")
    block = {"cmd": lines[0], "more": [], "tol": None, "values": []}
    for line in lines[1:]:
        if not line:
            continue
        if line.startswith("and "):
            block["more"].append(line[4:].strip())
            continue
        if line.startswith("tol "):
            block["tol"] = parse_tol(line[4:].strip(), where)
            continue
        m = VALUE.match(line)
        if not m:
            raise Malformed(f"{where}: '{line}' is neither 'tol X' nor 'VALUE @ REGEX [#K] [tol X]'")
        text, regex, k, tol = m.groups()
        if not NUM.fullmatch(text):
            raise Malformed(f"{where}: quoted value '{text}' is not a number")
        try:
            re.compile(regex, re.M)
        except re.error as e:
            raise Malformed(f"{where}: bad REGEX '{regex}': {e}")
        block["values"].append({"text": text, "regex": regex, "k": int(k or 1),
                                "tol": parse_tol(tol, where) if tol else None})
    if not block["values"]:
        raise Malformed(f"{where}: check mark names no value")
    if block["tol"] is None and any(v["tol"] is None for v in block["values"]):
        raise Malformed(f"{where}: no tolerance stated (tol X% or tol X)")
    return block


def flat(text):
    """A command as the shell reads it: continued lines joined, spaces collapsed."""
    return " ".join(text.replace("\\\n", " ").split())


def in_code(page, pos):
    """A mark shown as an example: in a fenced block, an indented code line or `code`."""
    before = page[:pos]
    if before.endswith("`"):
        return True
    if len(re.findall(r'^ {0,3}```', before, re.M)) % 2:
        return True
    line = before[before.rfind("\n") + 1:]
    return line.startswith("    ") and not line.strip()


def quoted(text, scope):
    """How often the value appears in the page's text as a whole number (not part of another)."""
    return len(re.findall(r'(?<![\d.])' + re.escape(text) + r'(?!\.?\d)', scope))


def printed(output, regex, k):
    m = re.search(regex, output, re.M)
    if not m:
        return None, f"'{regex}' not found in the output"
    nums = NUM.findall(output[m.end():])
    if len(nums) < k:
        return None, f"no number #{k} after '{regex}'"
    return float(nums[k - 1]), None


def workdir(root):
    """A folder whose entries link to the repository's, build/sunmc to $SUNMC."""
    d = tempfile.mkdtemp(prefix="docs-check.")
    for name in os.listdir(root):
        if name in ("build", "runs", ".git"):
            continue
        os.symlink(os.path.join(root, name), os.path.join(d, name))
    os.mkdir(os.path.join(d, "build"))
    sunmc = os.path.abspath(os.environ.get("SUNMC") or os.path.join(root, "build", "sunmc"))
    os.symlink(sunmc, os.path.join(d, "build", "sunmc"))
    return d


def run(cmd, cwd, timeout_s=TIMEOUT_S):
    try:
        p = subprocess.run(["bash", "-c", cmd], cwd=cwd, capture_output=True, text=True,
                           timeout=timeout_s)
    except subprocess.TimeoutExpired:
        return None, f"timed out after {timeout_s} s"
    if p.returncode != 0:
        return None, f"exited {p.returncode}: {p.stderr.strip()[-300:]}"
    return p.stdout + p.stderr, None


def quoted_failures(block, scope, where):
    """Each value line must stand for one place the text after the mark quotes it."""
    failures, marked, ok = [], {}, []
    for v in block["values"]:
        # a number marked twice (two table cells) and changed in one cell is
        # caught although the other cell still shows it
        marked[v["text"]] = marked.get(v["text"], 0) + 1
        n = quoted(v["text"], scope)
        if n == 0:
            failures.append(f"{where}: {v['text']} is marked but the text after the mark does not quote it")
        elif marked[v["text"]] > n:
            failures.append(f"{where}: {v['text']} is marked {marked[v['text']]} times but the text "
                            f"after the mark quotes it {n} times")
        else:
            ok.append(v)
    return failures, ok


def compare(values, output, where):
    failures = []
    for v in values:
        got, err = printed(output, v["regex"], v["k"])
        if err:
            failures.append(f"{where}: {v['text']}: {err}")
            continue
        tol, rel = v["tol"]
        allowed = tol * abs(got) if rel else tol
        if abs(float(v["text"]) - got) > allowed * (1 + 1e-9) + 1e-12:  # 5.9 vs 5.85 at 0.05
            failures.append(f"{where}: the page says {v['text']}, the command prints {got:g} "
                            f"(tolerance {tol * 100 if rel else tol:g}{'%' if rel else ''})")
    return failures


def check_page(path, root, counts, tiers):
    """tiers: the kinds of check mark whose commands run ('check', 'check-slow');
    the text of the others is still held to their marks."""
    with open(path, encoding="utf-8") as f:
        page = f.read()
    outside = MARK.sub("", page)
    marks = [m for m in MARK.finditer(page) if not in_code(page, m.start())]
    failures, output, cwd = [], None, None
    try:
        for i, m in enumerate(marks):
            line = page.count("\n", 0, m.start()) + 1
            where = f"{path}:{line}"
            kind = m.group(1)
            if kind not in ("check", "check-slow"):
                counts[kind] += 1
                continue
            block = parse_block(m.group(2), where)
            for v in block["values"]:
                v["tol"] = v["tol"] or block["tol"]
            end = marks[i + 1].start() if i + 1 < len(marks) else len(page)
            head = re.search(r'^#', page[m.end():end], re.M)
            scope = page[m.end():m.end() + head.start()] if head else page[m.end():end]
            cmds = [] if block["cmd"] == "same" else [block["cmd"]] + block["more"]
            missing = [c for c in cmds if flat(c) not in flat(outside)]
            if missing:
                failures.append(f"{where}: the command is not on the page: {missing[0]}")
                output = None
                continue
            text_failures, values = quoted_failures(block, scope, where)
            failures += text_failures
            if kind not in tiers:
                # not run in this tier: the text is held to the mark, the
                # command is not run (a `same` after it has nothing to reuse)
                counts["held_numbers"] += len(block["values"])
                counts["held_blocks"] += 1
                output = None
                continue
            counts["numbers"] += len(block["values"])
            if cmds:
                output = None
                cwd = cwd or workdir(root)
                limit = SLOW_TIMEOUT_S if kind == "check-slow" else TIMEOUT_S
                outs = [run(c, cwd, limit) for c in cmds]
                errs = [f"{c}: {e}" for c, (o, e) in zip(cmds, outs) if e]
                if errs:
                    failures.append(f"{where}: {errs[0]}")
                    continue
                output = "".join(o for o, e in outs)
            elif output is None:
                failures.append(f"{where}: '{kind}: same' without a command run before it")
                continue
            failures += compare(values, output, where)
            counts["blocks"] += 1
    finally:
        if cwd:
            shutil.rmtree(cwd, ignore_errors=True)
    return failures


def main(argv):
    root = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
    args = argv[1:]
    tiers = ("check", "check-slow") if os.environ.get("DOCS_CHECK_SLOW") == "1" else ("check",)
    if args and args[0] == "--slow":  # make docs-check-slow: only the slow tier's commands
        tiers, args = ("check-slow",), args[1:]
    pages = args or ["README.md"] + sorted(
        os.path.join("docs", p) for p in os.listdir(os.path.join(root, "docs")) if p.endswith(".md"))
    counts = {"blocks": 0, "numbers": 0, "held_blocks": 0, "held_numbers": 0, "machine": 0,
              "unchecked": 0}
    failures = []
    try:
        for p in pages:
            failures += check_page(p if os.path.isabs(p) else os.path.join(root, p) if not os.path.exists(p) else p,
                                   root, counts, tiers)
    except Malformed as e:
        print(f"docs-check: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        print(f"docs-check: {e}", file=sys.stderr)
        return 2
    for f in failures:
        print(f, file=sys.stderr)
    other = "make docs-check" if tiers == ("check-slow",) else "make docs-check-slow"
    print(f"docs-check: {counts['numbers']} numbers in {counts['blocks']} checks, "
          f"{len(failures)} failed; {counts['held_numbers']} numbers in {counts['held_blocks']} "
          f"checks not run here, held to the text only ({other} runs them); "
          f"{counts['machine']} marked machine-dependent, "
          f"{counts['unchecked']} marked unchecked", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
