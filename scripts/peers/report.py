"""The Markdown report of bench_peers.py: one table per model and a summary of ratios."""
import os
import platform
import shlex
import statistics
import sys

LABEL = {"arbor": "arbor", "open3d": "Open3D", "embree": "Embree", "embree-robust": "Embree robust", "fcpw": "fcpw", "fcpw-robust": "fcpw robust"}


def cpu_name():
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor()


def command_line():
    """The command that made the report, as typed (paths as given)."""
    return " ".join(shlex.quote(a) for a in ["/usr/bin/python3", "scripts/bench_peers.py"] + sys.argv[1:])


def fmt_ms(ms):
    return f"{ms:.2f}" if ms < 100 else f"{ms:.0f}"


def write_report(results, o):
    lines = [f"# arbor beside its Python peers", "",
             f"{o.threads} threads, {o.rays} rays and {o.points} points per query, median of {o.rounds} "
             f"interleaved rounds; {cpu_name()}.", "", "```sh", command_line(), "```", ""]
    for name, text in results[0]["describe"].items():
        lines.append(f"- {name}: {text}")
    if o.fcpw_missing:
        lines.append(f"- fcpw: left out: {o.fcpw_missing}")
    if o.note:
        lines += ["", o.note]
    lines.append("")
    PEERS = [p for p in results[0]["describe"] if p != "arbor"]
    summary = {}
    head = "| query | input | arbor ms | " + " | ".join(f"{LABEL[p]} ms | ratio" for p in PEERS) + \
           " | differ | refereed | wrong: " + " / ".join(LABEL[p] for p in ["arbor"] + PEERS) + " |"
    for res in results:
        lines += [f"## {res['name']} ({res['triangles']} triangles, {'closed' if res['closed'] else 'not closed'})", "",
                  head, "|---" * (head.count("|") - 1) + "|"]
        b = res["builds"]
        lines.append(f"| build | mesh | {fmt_ms(b['arbor'])} | "
                     + " | ".join(f"{fmt_ms(b[p])} | {b[p] / b['arbor']:.2f}" for p in PEERS) + " | | | |")
        for p in PEERS:
            summary.setdefault(("build", "mesh"), {}).setdefault(p, []).append(b[p] / b["arbor"])
        for row in res["rows"]:
            if "skipped" in row:
                lines.append(f"| {row['query']} | {row['input']} | skipped: {row['skipped']} |" + " |" * (2 * len(PEERS) + 3))
                continue
            ms = row["ms"]
            cells = []
            for peer in PEERS:
                if peer in ms:
                    ratio = ms[peer] / ms["arbor"]
                    summary.setdefault((row["query"], row["input"]), {}).setdefault(peer, []).append(ratio)
                    cells += [fmt_ms(ms[peer]), f"{ratio:.2f}"]
                else:
                    cells += ["—", ""]
            w = row["wrong"]
            wrong = " / ".join(str(w[p]) if p in w else "—" for p in ["arbor"] + PEERS)
            why = "grazing an outline" if row["input"] == "edge" else "on the surface"
            amb = f" ({row['ambiguous']} {why} left out)" if row["ambiguous"] else ""
            lines.append(f"| {row['query']} | {row['input']} | {fmt_ms(ms['arbor'])} | " + " | ".join(cells)
                         + f" | {row['differ']} | {row['refereed']}{amb} | {wrong} |")
        lines.append("")
    lines += ["## Summary: median over models of the ratio peer time / arbor time (above 1: arbor faster)", "",
              "| query | input | " + " | ".join(LABEL[p] for p in PEERS) + " |", "|---" * (len(PEERS) + 2) + "|"]
    for (query, kind), peers in summary.items():
        cells = [f"{statistics.median(peers[p]):.2f} (min {min(peers[p]):.2f})" if p in peers else "—" for p in PEERS]
        lines.append(f"| {query} | {kind} | " + " | ".join(cells) + " |")
    text = "\n".join(lines) + "\n"
    os.makedirs(os.path.dirname(os.path.abspath(o.out)), exist_ok=True)
    tmp = o.out + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, o.out)
    print(text)
