#!/usr/bin/env python3
"""Independent reference values for the UFF parser tests, computed with pyuff.

Reads every file under fixtures/uff-real/ and writes
parsers/tests/expected/uff_real.json: per file the dataset types in order, and
for dataset 58 the function/ordinate type, declared and read point counts,
node/direction fields, first/last abscissa and first/middle/last ordinate.
A few values of 164, 15, 2411, 82 and 55 are kept too.

Also reads parsers/tests/expected/uff_written.uff (a file written by our
writer, kept byte-exact by the test `uff_roundtrip::golden_file`) and writes
parsers/tests/expected/uff_written_pyuff.json with what pyuff reads from it;
the test `uff_roundtrip::pyuff_reads_our_file` compares that with our values.

Usage: python3 scripts/uff_expected.py   (installs pyuff with pip if missing)
"""
import json
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
FIXTURES = os.path.join(REPO, "fixtures", "uff-real")
EXPECTED = os.path.join(REPO, "parsers", "tests", "expected")

try:
    import pyuff
except ImportError:
    subprocess.check_call([sys.executable, "-m", "pip", "install", "--quiet", "pyuff"])
    import pyuff
import numpy as np


def num(v):
    v = float(v)
    return v if math.isfinite(v) else None


def value(v):
    """A real as a number, a complex as [re, im]."""
    if np.iscomplexobj(v):
        return [num(np.real(v)), num(np.imag(v))]
    return num(v)


def sets_of(path):
    u = pyuff.UFF(path)
    types = [int(t) for t in u.get_set_types()]
    sets = u.read_sets(list(range(len(types)))) if types else []
    if isinstance(sets, dict):
        sets = [sets]
    return types, sets


def describe58(d):
    data = np.asarray(d["data"])
    x = np.asarray(d["x"])
    n = len(data)
    mid = n // 2
    return {
        "binary": int(d.get("binary", 0)),
        "func_type": int(d["func_type"]),
        "ord_data_type": int(d["ord_data_type"]),
        "num_pts": int(d["num_pts"]),
        "len_data": n,
        "abscissa_spacing": int(d["abscissa_spacing"]),
        "abscissa_min": num(d["abscissa_min"]),
        "abscissa_inc": num(d["abscissa_inc"]),
        "rsp_node": int(d["rsp_node"]),
        "rsp_dir": int(d["rsp_dir"]),
        "ref_node": int(d["ref_node"]),
        "ref_dir": int(d["ref_dir"]),
        "id1": str(d["id1"]).strip(),
        "ordinate_units": str(d.get("ordinate_axis_units_lab", "")).strip(),
        "ordinate_len_exp": int(d.get("ordinate_len_unit_exp", 0)),
        "orddenom_force_exp": int(d.get("orddenom_force_unit_exp", 0)),
        "x_first": num(x[0]) if n else None,
        "x_last": num(x[n - 1]) if n else None,
        "mid_index": mid,
        "y_first": value(data[0]) if n else None,
        "y_mid": value(data[mid]) if n else None,
        "y_last": value(data[n - 1]) if n else None,
    }


def describe(t, d):
    if t == 58:
        return describe58(d)
    out = {}
    if t == 164:
        for k in ("units_code", "length", "force", "temp", "temp_offset"):
            out[k] = num(d[k]) if k != "units_code" else int(d[k])
    elif t in (15, 2411):
        out["nodes"] = len(d["node_nums"])
        out["first_node"] = int(d["node_nums"][0])
        out["first_xyz"] = [num(d["x"][0]), num(d["y"][0]), num(d["z"][0])]
    elif t == 82:
        out["trace_num"] = int(d["trace_num"])
        out["n_nodes"] = int(d["n_nodes"])
    elif t == 55:
        out["nodes"] = len(d["node_nums"])
        out["analysis_type"] = int(d["analysis_type"])
    return out


def fixtures():
    result = {}
    for sub in sorted(os.listdir(FIXTURES)):
        folder = os.path.join(FIXTURES, sub)
        if not os.path.isdir(folder):
            continue
        for name in sorted(os.listdir(folder)):
            rel = f"{sub}/{name}"
            path = os.path.join(folder, name)
            try:
                types, sets = sets_of(path)
                result[rel] = {
                    "types": types,
                    "datasets": [describe(t, d) for t, d in zip(types, sets)],
                }
            except Exception as e:  # pyuff cannot read it (e.g. truncated file)
                result[rel] = {"pyuff_error": f"{type(e).__name__}: {e}"}
            print(rel, "->", result[rel].get("types", result[rel].get("pyuff_error")))
    return result


def written():
    path = os.path.join(EXPECTED, "uff_written.uff")
    types, sets = sets_of(path)
    out = []
    for d in sets:
        data = np.asarray(d["data"])
        x = np.asarray(d["x"])
        out.append({
            "binary": int(d.get("binary", 0)),
            "ord_data_type": int(d["ord_data_type"]),
            "x": [num(v) for v in x],
            "y": [value(v) for v in data],
        })
    return {"types": types, "functions": out}


def main():
    os.makedirs(EXPECTED, exist_ok=True)
    with open(os.path.join(EXPECTED, "uff_real.json"), "w") as f:
        json.dump({"pyuff_version": pyuff.__version__, "files": fixtures()}, f, indent=1, sort_keys=True)
        f.write("\n")
    if not os.path.exists(os.path.join(EXPECTED, "uff_written.uff")):
        print("no uff_written.uff yet: run UFF_BLESS=1 cargo test -p frfup-parsers --test all uff_roundtrip::")
        return
    with open(os.path.join(EXPECTED, "uff_written_pyuff.json"), "w") as f:
        json.dump({"pyuff_version": pyuff.__version__, **written()}, f, indent=1, sort_keys=True)
        f.write("\n")
    print("wrote", EXPECTED)


if __name__ == "__main__":
    main()
