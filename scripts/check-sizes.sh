#!/usr/bin/env bash
# Lists the source files over MAX_FILE lines (default 600) and the C++ functions over MAX_FUNCTION
# lines (default 80), signature to closing brace, in lib/src, kernels and tool (or in the folders
# and files given). Exits 1 when it lists anything, 0 otherwise.
#   scripts/check-sizes.sh [PATH...]          MAX_FILE=600 MAX_FUNCTION=80 by default
#
# A function is a brace block whose opening statement has a parameter list and that opens at
# namespace or class scope (so lambdas and blocks inside a function count towards that function);
# comments, string and character literals are skipped first. It is a heuristic, not a parser: a
# macro that opens a brace it does not close would throw it off.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -eq 0 ]; then set -- lib/src kernels tool; fi
MAX_FILE=${MAX_FILE:-600} MAX_FUNCTION=${MAX_FUNCTION:-80} exec python3 - "$@" <<'EOF'
import os
import re
import sys

max_file = int(os.environ["MAX_FILE"])
max_function = int(os.environ["MAX_FUNCTION"])
extensions = (".cpp", ".h", ".hpp", ".cc", ".cu", ".cuh", ".inl")


def sources(paths):
    for path in paths:
        if os.path.isfile(path):
            yield path
            continue
        for root, dirs, files in os.walk(path):
            dirs.sort()
            for name in sorted(files):
                if name.endswith(extensions):
                    yield os.path.join(root, name)


def code_only(text):
    """The text with comments, string and character literals and preprocessor lines blanked
    (newlines kept, so line numbers stay)."""
    out = []
    i, n = 0, len(text)
    line_start = True
    while i < n:
        c = text[i]
        if line_start and c == "#":
            # A preprocessor line, with its continuations.
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append("\n")
                    i += 2
                    continue
                i += 1
            continue
        if c == "\n":
            line_start = True
            out.append(c)
            i += 1
            continue
        if not c.isspace():
            line_start = False
        if text.startswith("//", i):
            while i < n and text[i] != "\n":
                i += 1
            continue
        if text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append("\n" * text.count("\n", i, end))
            i = end
            continue
        raw = re.match(r'R"([^()\\ ]{0,16})\(', text[i:i + 20])
        if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            close = ")" + raw.group(1) + '"'
            end = text.find(close, i + raw.end())
            end = n if end < 0 else end + len(close)
            out.append('""' + "\n" * text.count("\n", i, end))
            i = end
            continue
        if c == '"' or (c == "'" and not (i > 0 and text[i - 1].isalnum())):
            # A digit separator (1'000) is not a character literal: skipped by the test above.
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(c + c)
            i = j + 1
            continue
        out.append(c)
        i += 1
    return "".join(out)


def kind_of(statement):
    s = " ".join(statement.split())
    if re.search(r"\bnamespace\b", s) and "(" not in s:
        return "scope"
    if re.match(r'^extern\s+"', s):
        return "scope"
    if re.search(r"\b(class|struct|union|enum)\b", s) and "(" not in s.split(":")[0]:
        return "scope"
    if "(" in s and not s.rstrip().endswith("="):
        return "function"
    return "other"


def functions(code):
    """(first line, last line, name) of each function body opened at namespace or class scope."""
    stack = []  # kinds of the open blocks
    statement, statement_line = "", None
    found = []
    line = 1
    for c in code:
        if c == "{":
            if all(k == "scope" for k in stack):
                kind = kind_of(statement)
                stack.append(kind)
                if kind == "function":
                    name = re.findall(r"(\boperator\s*\(\s*\)|\boperator\s*[^\s(]+|[~\w:]+)\s*\(", statement)
                    found.append([statement_line or line, None, name[0] if name else "?", len(stack)])
            else:
                stack.append("inner")
            statement, statement_line = "", None
        elif c == "}":
            if stack:
                if stack[-1] == "function":
                    for f in reversed(found):
                        if f[1] is None:
                            f[1] = line
                            break
                stack.pop()
            statement, statement_line = "", None
        elif c == ";":
            statement, statement_line = "", None
        else:
            if not c.isspace() and statement_line is None:
                statement_line = line
            statement += c
        if c == "\n":
            line += 1
    return [(first, last, name) for first, last, name, _ in found if last is not None]


listed = 0
for path in sources(sys.argv[1:]):
    with open(path, encoding="utf-8", errors="replace") as f:
        text = f.read()
    lines = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
    if lines > max_file:
        print(f"{path}: {lines} lines (file over {max_file})")
        listed += 1
    for first, last, name in functions(code_only(text)):
        length = last - first + 1
        if length > max_function:
            print(f"{path}:{first}: {name}: {length} lines (function over {max_function})")
            listed += 1
sys.exit(1 if listed else 0)
EOF
