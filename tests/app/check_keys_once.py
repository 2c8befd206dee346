#!/usr/bin/env python3
"""Each key written once: no key string appears twice in a model's source.

  check_keys_once.py IBVALVE SOURCE_DIR

For each model's source (app/<model>_model.cpp, and the files its keys are bound in, drivers/keys.cpp among them), the keys `ibvalve
keys <model>` lists are looked for in the files' string literals (comments left out): a literal that is the key, or names it in a message ("must be below
valve.max_area_fraction"). A key the model binds once is found once; one written again (read by its
name, or named in a message instead of through keys_.key_of) is found twice. Prints each model's count
of keys found more than once and what they are; exits 1 when any model has one.
"""
import pathlib
import re
import subprocess
import sys

MODELS = {
    "lumped": ["lumped_model.cpp"],
    "ibfe": ["ibfe_model.cpp"],
    "fluid": ["fluid_model.cpp"],
    "aortic-valve": ["aortic_valve_model.cpp", "aortic_valve_keys.cpp", "valve_mesh.cpp", "../drivers/keys.cpp"],
}

KEY_ROW = re.compile(r"^\| `([^`]+)` \|", re.MULTILINE)
# A C++ string literal, or a comment (matched so that what it holds is skipped).
TOKENS = re.compile(r'//[^\n]*|/\*.*?\*/|"((?:[^"\\\n]|\\.)*)"', re.DOTALL)


def declared_keys(ibvalve, model):
    """The model's keys, or None when this build has no such model (a subset of the folders)."""
    done = subprocess.run([ibvalve, "keys", model], capture_output=True, text=True)
    return set(KEY_ROW.findall(done.stdout)) if done.returncode == 0 else None


def literals(source):
    return [m.group(1) for m in TOKENS.finditer(source) if m.group(1) is not None]


def repeated_keys(keys, source):
    """The keys found more than once in the literals of `source`, with their counts."""
    counts = {}
    for text in literals(source):
        for key in keys:
            # The key as a whole word: not part of a longer key ("fluid.cells" in "nested.fluid.cells").
            counts[key] = counts.get(key, 0) + len(
                re.findall(r"(?<![\w.])" + re.escape(key) + r"(?![\w.])", text))
    return {key: n for key, n in sorted(counts.items()) if n > 1}


def main():
    ibvalve, source_dir = sys.argv[1], pathlib.Path(sys.argv[2])
    failed = False
    for model, files in MODELS.items():
        paths = [source_dir / "app" / file for file in files]
        keys = declared_keys(ibvalve, model)
        if keys is None or not all(path.exists() for path in paths):
            continue
        repeated = repeated_keys(keys, "\n".join(path.read_text() for path in paths))
        print(f"{model}: {len(repeated)} key(s) written more than once"
              + "".join(f"\n  {key}: {n} times" for key, n in repeated.items()))
        failed = failed or bool(repeated)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
