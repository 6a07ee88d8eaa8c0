"""Prints file:line: text of every locale-bound number conversion in the C++ files named on stdin.

Locale-bound: a printf-family call (printf, fprintf, sprintf, snprintf and their v forms) whose
format has a floating-point conversion (%f %e %g %a, any flags, width and precision), and number
parsing by strtod/strtof/strtold/atof, std::stod/stof/stold or a std::istringstream read into a
double. A call spanning several lines is seen whole. A line holding "locale-independent:" (a
comment saying why) is allowed. Used by scripts/check_style.sh.
"""
import re
import sys

FLOAT = re.compile(r"%[-+ #0]*[0-9*]*(\.[0-9*]+)?L?[fFeEgGaA]")
PRINTF = re.compile(r"\b(?:std::)?v?(?:printf|fprintf|sprintf|snprintf|dprintf)\s*\(")
PARSE = re.compile(r"\b(?:std::)?(?:strtod|strtof|strtold|atof|stod|stof|stold)\s*\(")
STREAM = re.compile(r"\bistringstream\b[^;]*>>\s*\w*(?:double|float|_mm|_rad)\b")


def CallText(text, start):
    """The text of the call whose '(' ends at `start`, up to its matching ')'."""
    depth, i, in_string = 1, start, False
    while depth and i < len(text):
        c = text[i]
        if in_string:
            if c == "\\":
                i += 1
            elif c == '"':
                in_string = False
        elif c == '"':
            in_string = True
        elif c == "(":
            depth += 1
        elif c == ")":
            depth -= 1
        i += 1
    return text[start:i]


def Problems(path):
    text = open(path, encoding="utf-8", errors="replace").read()
    lines = text.split("\n")
    found = []
    for match in PRINTF.finditer(text):
        call = CallText(text, match.end())
        literals = "".join(re.findall(r'"((?:[^"\\]|\\.)*)"', call))
        if FLOAT.search(literals):
            found.append(text.count("\n", 0, match.start()))
    for pattern in (PARSE, STREAM):
        for match in pattern.finditer(text):
            found.append(text.count("\n", 0, match.start()))
    for index in sorted(set(found)):
        if "locale-independent:" in lines[index]:
            continue
        print(f"{path}:{index + 1}: {lines[index].strip()}")


for name in sys.stdin.read().split():
    Problems(name)
