#!/usr/bin/env python3
"""Compare the estimates of two lt files bit for bit, leaving out what differs between runs by nature.

    lt_compare.py A B    exit 0 when A and B hold the same estimates, 1 (with one line per difference) when not

Compared exactly: every BUFR and PATH payload; every SNAP's sample count and buffer; every CHST's mutation
count, b, b's sample count and states; every STAT table's rows and columns (in order) and values, but for the
values of the columns and rows that hold times (seconds, rates); INFO's "parameters" object. Left out: INFO's command, times and version, the
times of SNAP and CHST chunks, and the order of STAT tables (a tool may write them in another order).
Standard library only (formats/SPEC.md).
"""
import json
import struct
import sys

TIME_WORDS = ("seconds", "per_second", "rate")


def chunks(path):
    with open(path, "rb") as f:
        data = f.read()
    magic, _version, kind = struct.unpack_from("<4sII", data, 0)
    if magic != b"LTF\x01":
        sys.exit(f"{path}: not an lt file")
    at, out = 12, []
    while at < len(data):
        tag, length = struct.unpack_from("<4sQ", data, at)
        out.append((tag.decode(), data[at + 12:at + 12 + length]))
        at += 12 + length + 4
    return kind, out


def stat_table(payload):
    at = 0

    def string():
        nonlocal at
        (n,) = struct.unpack_from("<I", payload, at)
        s = payload[at + 4:at + 4 + n].decode()
        at += 4 + n
        return s

    name = string()
    columns, rows = struct.unpack_from("<II", payload, at)
    at += 8
    cols = [string() for _ in range(columns)]
    names = [string() for _ in range(rows)]
    values = struct.unpack_from(f"<{rows * columns}d", payload, at)
    table = {("order of rows", "and columns"): (tuple(names), tuple(cols))}
    for r, row in enumerate(names):
        for c, col in enumerate(cols):
            if any(w in row or w in col for w in TIME_WORDS):
                continue
            table[(row, col)] = values[r * columns + c]
    return name, table


def summary(path):
    kind, parts = chunks(path)
    out = {"kind": kind, "estimates": [], "stats": {}}
    for tag, payload in parts:
        if tag == "INFO":
            out["parameters"] = json.loads(payload).get("parameters")
        elif tag in ("BUFR", "PATH"):
            out["estimates"].append((tag, payload))
        elif tag == "SNAP":
            (samples,) = struct.unpack_from("<Q", payload, 16)
            out["estimates"].append((tag, samples, payload[32:]))
        elif tag == "CHST":
            mutations, b, b_samples = struct.unpack_from("<QdQ", payload, 0)
            out["estimates"].append((tag, mutations, b, b_samples, payload[40:]))
        elif tag == "STAT":
            name, table = stat_table(payload)
            out["stats"][name] = table
    return out


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    a, b = (summary(p) for p in sys.argv[1:])
    problems = []
    if a["kind"] != b["kind"]:
        problems.append("file kinds differ")
    if a.get("parameters") != b.get("parameters"):
        problems.append(f"INFO parameters differ: {a.get('parameters')} | {b.get('parameters')}")
    if len(a["estimates"]) != len(b["estimates"]):
        problems.append(f"{len(a['estimates'])} against {len(b['estimates'])} estimate chunks")
    for i, (x, y) in enumerate(zip(a["estimates"], b["estimates"])):
        if x != y:
            problems.append(f"estimate chunk {i + 1} ({x[0]}) differs")
    for name in sorted(set(a["stats"]) | set(b["stats"])):
        x, y = a["stats"].get(name), b["stats"].get(name)
        if x is None or y is None:
            problems.append(f"STAT {name}: only in {'B' if x is None else 'A'}")
        elif x != y:
            keys = sorted(k for k in set(x) | set(y) if x.get(k) != y.get(k))
            problems.append(f"STAT {name} differs at {keys[:4]}: {[x.get(k) for k in keys[:4]]} | "
                            f"{[y.get(k) for k in keys[:4]]}")
    for p in problems:
        print(f"{sys.argv[1]} ~ {sys.argv[2]}: {p}")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
