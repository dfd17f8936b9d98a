#!/usr/bin/python3
"""Generates the fuzz corpus kept in corpus/ (deterministic: the same seed gives the
same files; rerun after changing a base case or the mutation rules, and commit).

  corpus/cases/    500 mutants of the base cases in base/ (TOML text)
  corpus/grids/    200 mutants of a two-block Plot3D grid (text, Fortran and raw binary)
  corpus/sets.txt  100 hostile --set assignments, each with the base case it goes with
  corpus/restarts.txt  50 recipes for restart.h5 mutants: byte flips, truncations,
                   appended bytes at fixed fractions of the file, and files written by
                   other runs (another turbulence model, another grid); run_fuzz.py
                   writes the base restarts with the narwhal under test and applies the
                   recipes, so the corpus follows the restart format.
"""
import random
import re
import shutil
import struct
import tomllib
from pathlib import Path

HERE = Path(__file__).resolve().parent
BASE = HERE / "base"
OUT = HERE / "corpus"
SEED = 14

HOSTILE = ["-1", "0", "1", "2147483647", "2147483648", "4294967297", "-2147483649", "9223372036854775807",
           "1000000000", "1e9", "1e308", "-1e308", "5e-324", "nan", "inf", "-inf", "-0.0", "0.5", '"abc"', '""',
           "true", "[]", "[1, 2]", "[nan, 0.0, 0.0]", "[1.0, 0.0]", "[1e308, 1e308, 1e308]", "{}", "{ a = 1 }",
           "1979-05-27", '"../../../../etc/passwd"', '"\\u0000"', "0x7fffffff", "-0x1"]


def base_cases():
    return sorted(p for p in BASE.glob("*.toml"))


def value_lines(lines):
    return [i for i, l in enumerate(lines) if re.match(r"^\s*[A-Za-z_][\w.]*\s*=", l)]


def mutate_case(text, rng):
    lines = text.splitlines()
    vals = value_lines(lines)
    op = rng.choice(["value", "value", "value", "value", "delete", "duplicate", "rename", "garbage", "truncate",
                     "table", "unknown", "flip", "type"])
    if op == "value" and vals:
        i = rng.choice(vals)
        key = lines[i].split("=", 1)[0]
        lines[i] = f"{key}= {rng.choice(HOSTILE)}"
    elif op == "delete" and vals:
        del lines[rng.choice(vals)]
    elif op == "duplicate" and vals:
        i = rng.choice(vals)
        lines.insert(i, lines[i])
    elif op == "rename" and vals:
        i = rng.choice(vals)
        key, rest = lines[i].split("=", 1)
        k = key.strip()
        j = rng.randrange(len(k))
        k = k[:j] + k[j + 1:] if rng.random() < 0.5 else k[:j] + rng.choice("aeiou_x") + k[j:]
        lines[i] = f"{k} ={rest}"
    elif op == "garbage":
        i = rng.randrange(len(lines) + 1)
        lines.insert(i, rng.choice(["\x00\x01\x02", "[[[", "= 1", "a = ", "[flow", "]]", "\"unterminated",
                                    "\ufeffkey = 1", "a.b.c.d.e = 1", "[bc.]", "x = 1 # \x7f"]))
    elif op == "truncate":
        t = "\n".join(lines)
        return t[:rng.randrange(len(t))]
    elif op == "table":
        heads = [i for i, l in enumerate(lines) if l.startswith("[")]
        if heads:
            i = rng.choice(heads)
            lines[i] = rng.choice(["[grid]", "[flow]", "[solver]", "[[periodic]]", "[bc.nowhere]", "[turbulence]",
                                   "[output]", "[parallel]", "[bc]", "[case.sub]", "[[grid.patch]]"])
    elif op == "unknown":
        heads = [i for i, l in enumerate(lines) if l.startswith("[")] or [0]
        lines.insert(rng.choice(heads) + 1, f"{rng.choice(['cfl', 'reynold', 'typ', 'velocty', 'zzz'])} = 1")
    elif op == "flip":
        t = bytearray("\n".join(lines).encode())
        if t:
            t[rng.randrange(len(t))] ^= 1 << rng.randrange(8)
        return t.decode("utf-8", errors="replace")
    elif op == "type" and vals:
        i = rng.choice(vals)
        key, rest = lines[i].split("=", 1)
        rest = rest.strip()
        lines[i] = f"{key}= " + (f'"{rest}"' if not rest.startswith('"') else rest.strip('"') or "1")
    return "\n".join(lines) + "\n"


# ---- grids ----------------------------------------------------------------------------

def box_blocks():
    """Two 4 x 4 x 1-cell blocks side by side: x in [0, 1] and [1, 2], y in [0, 1], z in [0, 0.1]."""
    blocks = []
    for b in range(2):
        n = (5, 5, 2)
        xyz = [[], [], []]
        for k in range(n[2]):
            for j in range(n[1]):
                for i in range(n[0]):
                    xyz[0].append(b + i / 4.0)
                    xyz[1].append(j / 4.0)
                    xyz[2].append(0.1 * k)
        blocks.append((n, xyz))
    return blocks


def grid_text(blocks):
    s = f"{len(blocks)}\n" + "".join(f"{n[0]} {n[1]} {n[2]}\n" for n, _ in blocks)
    for _, xyz in blocks:
        for c in range(3):
            s += " ".join(repr(v) for v in xyz[c]) + "\n"
    return s.encode()


def grid_binary(blocks, fortran, fmt="d"):
    rec = lambda payload: (struct.pack("<i", len(payload)) + payload + struct.pack("<i", len(payload))) if fortran else payload  # noqa: E731
    out = rec(struct.pack("<i", len(blocks)))
    out += rec(b"".join(struct.pack("<3i", *n) for n, _ in blocks))
    for _, xyz in blocks:
        out += rec(b"".join(struct.pack(f"<{len(xyz[c])}{fmt}", *xyz[c]) for c in range(3)))
    return out


HOSTILE_INTS = [0, 1, -1, 2, 3, 65537, 100000, 2**31 - 1, -2**31, 2**30, 1024, 400]


def mutate_grid(data, text, rng):
    data = bytearray(data)
    op = rng.choice(["header", "header", "flip", "truncate", "append", "token", "token", "zero"] if text else
                    ["header", "header", "header", "flip", "flip", "truncate", "append", "nan", "marker"])
    if op == "header":
        if text:
            toks = data.decode().split("\n")
            line = rng.randrange(min(3, len(toks)))
            parts = toks[line].split() or ["1"]
            parts[rng.randrange(len(parts))] = str(rng.choice(HOSTILE_INTS))
            toks[line] = " ".join(parts)
            return "\n".join(toks).encode()
        fortran = data[:4] == struct.pack("<i", 4)
        words = [1, 4, 5, 6, 7, 8, 9] if fortran else [0, 1, 2, 3, 4, 5, 6]
        w = rng.choice(words)
        data[4 * w:4 * w + 4] = struct.pack("<i", rng.choice(HOSTILE_INTS))
    elif op == "flip":
        i = rng.randrange(len(data))
        data[i] ^= 1 << rng.randrange(8)
    elif op == "truncate":
        return bytes(data[:rng.randrange(1, len(data))])
    elif op == "append":
        return bytes(data) + bytes(rng.randrange(256) for _ in range(rng.randrange(1, 64)))
    elif op == "token":
        toks = data.decode().split()
        toks[rng.randrange(len(toks))] = rng.choice(["nan", "inf", "-inf", "1e999", "abc", "-", "0x10", "1.0D+00",
                                                      "1,5", "", "99999999999999999999"])
        return (" ".join(toks) + "\n").encode()
    elif op == "zero":
        i = rng.randrange(len(data))
        data[i:i + 8] = b"\0" * 8
    elif op == "nan":
        i = 4 * rng.randrange(len(data) // 4)
        data[i:i + 8] = struct.pack("<d", float(rng.choice(["nan", "inf"])))[: len(data[i:i + 8])]
    elif op == "marker":
        i = rng.choice([0, 8, 12, len(data) - 4])
        data[i:i + 4] = struct.pack("<i", rng.choice(HOSTILE_INTS))
    return bytes(data)


# ---- --set assignments ------------------------------------------------------------------

def keys_of(path):
    def walk(t, prefix):
        for k, v in t.items():
            if isinstance(v, dict):
                yield from walk(v, f"{prefix}{k}.")
            elif isinstance(v, list) and v and isinstance(v[0], dict):
                for i, sub in enumerate(v):
                    yield from walk(sub, f"{prefix}{k}[{i}].")
            else:
                yield prefix + k
    with open(path, "rb") as f:
        return list(walk(tomllib.load(f), ""))


SYNTAX = ["=", "=1", "key", "flow.reynolds", "flow.reynolds=", "flow..reynolds=1", ".flow=1", "flow.=1",
          "grid.patch[x].label=\"a\"", "grid.patch[99].range_i=[0, 1]", "grid.patch[-1].block=1",
          "grid.patch[0.block=1", "flow=1", "flow.reynolds.x=1", "bc.inlet=\"wall\"", "solver.max_iterations=1 2",
          "flow.reynolds=1e5 # comment", "grid.type=\"plot3d\"", "grid.file=\"/nonexistent.xyz\"",
          "turbulence.model=\"k-omega\""]


def main():
    rng = random.Random(SEED)
    if OUT.exists():
        shutil.rmtree(OUT)
    (OUT / "cases").mkdir(parents=True)
    (OUT / "grids").mkdir()
    bases = base_cases()
    blocks = box_blocks()
    (BASE / "box.xyz").write_bytes(grid_text(blocks))
    shutil.copy(BASE / "box.xyz", OUT / "cases" / "box.xyz")  # the Plot3D base's grid, beside its mutants
    for n in range(500):
        b = bases[n % len(bases)]
        (OUT / "cases" / f"{n:03d}_{b.stem}.toml").write_text(mutate_case(b.read_text(), rng), errors="replace")
    grids = {"text": grid_text(blocks), "fortran": grid_binary(blocks, True), "raw": grid_binary(blocks, False),
             "raw_single": grid_binary(blocks, False, "f")}
    names = sorted(grids)
    for n in range(200):
        kind = names[n % len(names)]
        (OUT / "grids" / f"{n:03d}_{kind}.xyz").write_bytes(mutate_grid(grids[kind], kind == "text", rng))
    sets = []
    for n in range(100):
        b = bases[n % len(bases)]
        if n % 5 == 4:
            assignment = SYNTAX[(n // 5) % len(SYNTAX)]
        else:
            assignment = f"{rng.choice(keys_of(b))}={rng.choice(HOSTILE)}"
        sets.append(f"{b.name}\t{assignment}")
    (OUT / "sets.txt").write_text("# base case<TAB>--set assignment (one per line)\n" + "\n".join(sets) + "\n")
    recipes = [f"flip {rng.random():.6f} {rng.randrange(1, 256)}" for _ in range(36)]
    recipes += [f"flip_header {rng.randrange(0, 160)} {rng.randrange(1, 256)}" for _ in range(6)]
    recipes += ["truncate 0.5", "truncate 0.999", "append 1", "append 4096", "empty",
                "model sa", "grid grid.cells_normal=12", "grid grid.length=2.0"]
    (OUT / "restarts.txt").write_text(
        "# recipe per line: flip <fraction of the file> <xor>, flip_header <byte> <xor>, truncate <fraction>,\n"
        "# append <bytes>, empty, model <turbulence model>, grid <override> (see make_corpus.py)\n"
        + "\n".join(recipes) + "\n")
    print(f"corpus: 500 cases, 200 grids, {len(sets)} --set values, {len(recipes)} restart recipes in {OUT}")


if __name__ == "__main__":
    main()
