#!/usr/bin/python3
"""scripts/function-lengths finds what it must and nothing else, then holds the tree to it.

Usage: check_function_lengths.py SCRIPT ROOT ALLOW
  1. fixtures in a temporary folder: a 101-line function is found (and named), a 100-line one is not;
     a constructor whose member initializers use braces, class members with brace defaults, braces in
     comments, strings, raw strings and character literals, a namespace-scope initializer and a lambda
     inside a function do not mislead it; an allowance passes a long function and goes stale when it is
     split;
  2. the tree at ROOT has no function over 100 lines but those ALLOW names.
"""
import os
import subprocess
import sys
import tempfile

script, root, allow = sys.argv[1:4]


def body(lines):
    return "".join(f"  x += {i};\n" for i in range(lines))


def run(*args):
    return subprocess.run([sys.executable, script, *args], capture_output=True, text=True)


failures = []


def expect(what, condition, detail=""):
    if not condition:
        failures.append(f"{what}: {detail}")


with tempfile.TemporaryDirectory() as folder:
    source = os.path.join(folder, "sample.cpp")
    # long_one: its declaration line, "{", 97 lines, its return, "}" = 101 lines; just_right: 100.
    text = (
        "#include <string>\n"
        "#define BRACE {\n"
        "namespace demo {\n"
        "const char* text = \"} { }\"; // } {\n"
        "const char* raw = R\"x(}})x\";\n"
        "const char quote = '}';\n"
        "const int table[] = {1, 2, 3};\n"
        "struct Holder {\n"
        "  int value{0};\n"
        "  Holder(int a) : value{a}, other_(a) {}\n"
        "  int other_;\n"
        "  int get() const { return value; }\n"
        "};\n"
        "/* a comment { with braces */\n"
        "int long_one(int x)\n{\n" + body(97) + "  return x;\n}\n"
        "int just_right(int x)\n{\n" + body(96) + "  return x;\n}\n"
        "int with_lambda(int x)\n{\n  auto f = [&](int y) {\n    return x + y;\n  };\n  return f(1);\n}\n"
        "} // namespace demo\n")
    with open(source, "w") as f:
        f.write(text)
    listing = run("--all", source)
    names = {line.split()[1]: int(line.split()[2]) for line in listing.stdout.splitlines()}
    expect("every function found with its length",
           names == {"Holder": 1, "get": 1, "long_one": 101, "just_right": 100, "with_lambda": 7},
           listing.stdout)
    long_ones = run(source)
    expect("the 101-line function alone reported, exit 1",
           long_ones.returncode == 1 and long_ones.stdout.split() == [f"{source}:15", "long_one", "101"],
           f"exit {long_ones.returncode}: {long_ones.stdout}")
    allowance = os.path.join(folder, "allow.txt")
    with open(allowance, "w") as f:
        f.write(f"# waiting\n{source} long_one\n")
    allowed = run("--allow", allowance, source)
    expect("an allowed function passes", allowed.returncode == 0, allowed.stdout + allowed.stderr)
    with open(source, "w") as f:
        f.write(text.replace(body(97), body(10), 1))
    stale = run("--allow", allowance, source)
    expect("a split function left on the list fails",
           stale.returncode == 1 and "no longer over 100 lines" in stale.stdout, stale.stdout)
    missing = run(os.path.join(folder, "nothing.cpp"))
    expect("a missing path is exit 2", missing.returncode == 2, missing.stderr)

tree = run("--root", root, "--allow", allow)
expect("the tree: no function over 100 lines but those allowed", tree.returncode == 0, tree.stdout)

for failure in failures:
    print("FAIL " + failure)
print("ok" if not failures else f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
