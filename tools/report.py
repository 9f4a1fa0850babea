#!/usr/bin/python3
"""shvol report: plots and tables of a batch's ledger (DIR/results.jsonl).

Usage: report.py DIR COLUMNS QUIET   (shvol report DIR runs this with Debian's /usr/bin/python3;
COLUMNS are the ledger's columns that are no axes, comma-separated: shvol's list, kept in one
place, io/ledger.h; QUIET is --quiet, or empty to name the files written on stderr)

Writes DIR/report.md and DIR/report.html with:
  - error vs time per configuration, log-log, the Pareto front over all points marked;
  - error vs spp per configuration, log-log, with a 1/sqrt(spp) slope for scale (1/spp for relmse);
  - time vs each axis;
  - a table: per configuration and spp, the mean error over repeats +- its standard deviation,
    the mean time, and the efficiency 1/(MSE x time) when RMSE is known.
The time is each image's total_s (loading and set-up included) when every row has it, else the
passes' wall_time_s (ledgers from before 6 Dec).
A configuration is one combination of the sweep's axis values other than spp (repeats pooled).
"""
import html
import json
import math
import os
import re
import signal
import sys

SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


class Interrupted(Exception):
    """A signal that ends the report (SIGINT, SIGTERM or SIGHUP): raised where the script can
    stop cleanly (stop_if_signalled), so that its temporaries are removed on the way out
    (Python's own SIGTERM and SIGHUP ended it at once, leaving a plot's temporary; helper 100)."""

    def __init__(self, number):
        super().__init__(number)
        self.number = number


def on_signal(number, frame):
    # Only noted: an exception raised from a handler can land in a finaliser or in importlib,
    # which print it and carry on (a Ctrl-C during the import of matplotlib came out as a
    # traceback and "needs matplotlib"). Later signals (Ctrl-C reaches the whole process group,
    # and shvol passes its own signal on too) change nothing.
    if not on_signal.number:
        on_signal.number = number


on_signal.number = 0


def stop_if_signalled():
    if on_signal.number:
        raise Interrupted(on_signal.number)


# A signal the caller ignores stays ignored. shvol report starts the script with these signals
# blocked, released once the handlers are in place: a Ctrl-C while Python started up made it
# print "Fatal Python error" and a traceback.
for _s in SIGNALS:
    if signal.getsignal(_s) in (signal.SIG_DFL, signal.default_int_handler):
        signal.signal(_s, on_signal)
signal.pthread_sigmask(signal.SIG_UNBLOCK, SIGNALS)

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams["figure.max_open_warning"] = 0  # (all figures stay open until written)
except ImportError:
    sys.exit("shvol: error: report.py: needs matplotlib for /usr/bin/python3: apt-get install "
             "python3-matplotlib (./setup.sh installs it)")

ERRORS = ["rmse", "relmse", "mae"]
# Samples per pixel below which the z-test's standard errors are unreliable: shvol's
# kZTestReliableSpp (core/image_metrics.h).
ZTEST_RELIABLE_SPP = 64


def fail(message):
    """One line, as shvol's own errors, and exit code 1."""
    sys.exit(f"shvol: error: {message}")


def is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def load(directory):
    """The ledger's rows, and the number of its last line where a kill cut it short and it is
    left out (else None)."""
    path = os.path.join(directory, "results.jsonl")
    rows = []
    cut_short = None
    first_line = {}  # run id -> the line that has it
    try:
        # (utf-8-sig: a byte-order mark before the first row is skipped, as the batch skips it)
        f = open(path, encoding="utf-8-sig", errors="replace")
    except OSError as e:
        fail(f"{path}: cannot open file ({e.strerror})")
    with f:
        lines = f.readlines()
        for n, line in enumerate(lines, 1):
            if n % 10000 == 0:  # (a ledger of a million rows takes seconds)
                stop_if_signalled()
            if not line.strip():
                continue
            # A last line without its newline is a row a kill cut short: the next start of the
            # batch drops it (and keeps a whole one), so the report leaves it out.
            if n == len(lines) and not line.endswith("\n"):
                try:
                    if not isinstance(json.loads(line), dict):
                        cut_short = n
                        continue
                except (json.JSONDecodeError, RecursionError):
                    cut_short = n
                    continue
            try:
                row = json.loads(line)
            except json.JSONDecodeError:
                fail(f"{path}: line {n}: malformed JSON row")
            except RecursionError:  # (a traceback before; the batch refuses it too: helper 99)
                fail(f"{path}: line {n}: objects and arrays nested too deep")
            if not isinstance(row, dict):
                fail(f"{path}: line {n}: a row must be a JSON object")
            # The columns the batch compares are strings, as the batch's own reading requires
            # (the report took other types: helper 98).
            for key in ("fingerprint", "settings_fingerprint", "git_revision",
                        "reference_fingerprint"):
                if key in row and not isinstance(row[key], str):
                    fail(f"{path}: line {n}: \"{key}\" is not a string")
            # What the report reads of every row: a ledger written by shvol batch has them.
            for key in ("wall_time_s", "spp"):
                if key not in row:
                    fail(f"{path}: line {n}: no \"{key}\" (not a row of shvol batch)")
            # (At most 1e100: no image of floats gives more, and the report's squares and
            # products of such numbers stay finite; 1e308 ended it in a traceback, helper 130.)
            for key in ["wall_time_s", "spp"] + [k for k in ["total_s"] + ERRORS + ["bias"]
                                                 if k in row]:
                if (not is_number(row[key]) or row[key] < 0 and key != "bias"
                        or abs(row[key]) > 1e100):
                    fail(f"{path}: line {n}: {key}: expected a finite number"
                         f"{'' if key == 'bias' else ' >= 0'} of at most 1e100, got "
                         f"{json.dumps(row[key])}")
            if "ztest_passed" in row and not (isinstance(row["ztest_passed"], bool) and
                                              is_number(row.get("ztest_min_p"))):
                fail(f"{path}: line {n}: ztest_passed: expected true or false with a finite "
                     f"ztest_min_p, got {json.dumps(row['ztest_passed'])} and "
                     f"{json.dumps(row.get('ztest_min_p'))}")
            if not (isinstance(row["spp"], int) and row["spp"] >= 1):  # (a log axis)
                fail(f"{path}: line {n}: spp: expected an integer >= 1, got "
                     f"{json.dumps(row['spp'])}")
            # One error metric for the whole report: rows measured by other metrics than the
            # first row's would switch it (a row without rmse turned every row's to relmse, and
            # dropped the efficiency column). shvol batch writes rows of one list of metrics.
            measured = [k for k in ERRORS if k in row]
            if not rows:
                first_measured = measured
            elif measured != first_measured:
                fail(f"{path}: line {n}: measured by {', '.join(measured) or 'no error metric'}, "
                     f"the first row by {', '.join(first_measured) or 'none'}: not the rows of "
                     "one batch")
            # (A run in two rows would be counted twice; shvol batch refuses such a ledger too.)
            run = row.get("run")
            # (as shvol batch names its runs; "zzz" was reported as a run: helper 127)
            if not (isinstance(run, str) and re.fullmatch(r"r[0-9]{4,9}", run) and
                    run == "r%04d" % int(run[1:])):
                fail(f"{path}: line {n}: run: expected a run id of shvol batch (r0000, r0001, "
                     f"…), got {json.dumps(run)}")
            if run in first_line:
                fail(f"{path}: line {n}: run {run} again (first at line "
                     f"{first_line[run]}): two batches wrote into this directory")
            first_line[run] = n
            rows.append(row)
    if not rows:
        fail(f"{path}: no finished runs to report")
    return rows, cut_short


def canonical(v):
    """v with integral floats as integers, in objects and arrays too: 38.0 is 38, as shvol batch
    takes it (the batch resumed [38.0] as [38], and the report split them; helper 86)."""
    if isinstance(v, float) and v.is_integer():
        return int(v)
    if isinstance(v, dict):
        return {k: canonical(x) for k, x in v.items()}
    if isinstance(v, list):
        return [canonical(x) for x in v]
    return v


def value_text(v):
    return json.dumps(canonical(v), separators=(",", ":"))


def label(row, axes):
    parts = [f"{a}={value_text(row.get(a))}" for a in axes]
    return ", ".join(parts) if parts else "(all runs)"


def md_cell(text):
    """A table cell of report.md: a | would end it (helper 86: an axis value sky|2.exr)."""
    return text.replace("|", "\\|")


def counted(n, noun):
    """'1 run', '16 runs'."""
    return f"{n} {noun}" + ("" if n == 1 else "s")


def mean_sd(xs):
    m = sum(xs) / len(xs)
    sd = math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1)) if len(xs) > 1 else 0.0
    return m, sd


def pareto(points):
    """Indices of the points no other point beats in both time and error."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], math.inf
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def main():
    if len(sys.argv) != 4 or sys.argv[3] not in ("", "--quiet"):
        fail("usage: report.py DIR COLUMNS QUIET (run by shvol report, which passes the "
             "ledger's columns that are no axes, comma-separated, and --quiet or \"\")")
    directory, meta = sys.argv[1], set(sys.argv[2].split(","))
    stop_if_signalled()
    rows, cut_short = load(directory)
    stop_if_signalled()
    axes = [k for k in rows[0] if k not in meta]
    for r in rows[1:]:
        axes += [k for k in r if k not in meta and k not in axes]
    # An axis equal to every row's spp is the spp axis written otherwise (render.spp): spp is no
    # part of a configuration (as render.spp it split the error-vs-spp curves into points).
    axes = [a for a in axes if not all(r.get(a) == r["spp"] for r in rows)]
    error = next((e for e in ERRORS if all(e in r for r in rows)), None)
    # The time an image cost: since its render started, loading and set-up (a radiance cache's
    # fill, SH fits, tables) included, when every row has it (total_s, from 6 Dec); before, the
    # passes only (wall_time_s), which left a cached run's fill out of its cost (helper 67: 0.0033
    # s in the ledger for 1.37 s).
    time_key = "total_s" if all("total_s" in r for r in rows) else "wall_time_s"
    time_label = ("time per image (s), loading and set-up included" if time_key == "total_s"
                  else "wall time of the passes per image (s)")

    # groups[(config, spp)] -> rows (the repeats)
    groups = {}
    for r in rows:
        groups.setdefault((label(r, axes), r.get("spp")), []).append(r)
    # Configurations as their first runs come (r0000, …, r9999, r10000): the sweep's order, with
    # configurations added to a finished batch after those it had (shvol batch keeps the ids).
    by_run = sorted(rows, key=lambda r: (len(str(r.get("run", ""))), str(r.get("run", ""))))
    configs = list(dict.fromkeys(label(r, axes) for r in by_run))
    # The z-test's column when every row has one: the runs that passed of the configuration's,
    # and the smallest p of them (it was left out of the report; helper 67).
    ztest = all("ztest_passed" in r for r in rows)
    # The bias with its 95% interval when every row has them: a configuration every repeat of
    # which lies outside its interval is biased against the reference, and its 1/(MSE·time) ranks
    # it against unbiased ones unfairly (helper 86: an SH fit of order 4, biased in every repeat,
    # read twice HG's efficiency at 64 spp).
    biased_col = all("bias" in r and "bias_ci95" in r for r in rows)
    # The efficiency needs the RMSE: without it the column was there, empty, and nothing said why
    # (helper 141).
    efficient = error == "rmse"
    flagged = []
    unreliable = []
    summary = []  # (config, spp, n, err mean, err sd, time mean, efficiency, z-test, bias)
    for (c, spp), rs in sorted(groups.items(), key=lambda kv: (configs.index(kv[0][0]), kv[0][1])):
        t, _ = mean_sd([r[time_key] for r in rs])
        if error:
            e, sd = mean_sd([r[error] for r in rs])
        else:
            e, sd = math.nan, math.nan
        # 1/(MSE x time) with the MSE's mean over the repeats (not the mean RMSE squared).
        mse = sum(r["rmse"] ** 2 for r in rs) / len(rs) if efficient else math.nan
        eff = 1 / (mse * t) if efficient and mse > 0 and t > 0 else math.nan
        z = (f"{sum(r['ztest_passed'] for r in rs)}/{len(rs)} "
             f"(min p {min(r['ztest_min_p'] for r in rs):.2g})" if ztest else "")
        # Below ZTEST_RELIABLE_SPP the standard errors are too poor for the z-test: unbiased runs
        # fail it (helper 122: every repeat of the default scene at 2 and 4 spp, p down to 1e-277),
        # and the column read as a biased renderer.
        if ztest and is_number(spp) and spp < ZTEST_RELIABLE_SPP:
            z += " §"
            unreliable.append(f"{c} at {spp} spp")
        b = ""
        if biased_col:
            b = f"{mean_sd([r['bias'] for r in rs])[0]:.3g}"
            # Two repeats at least, each outside its interval on the same side: one alone would
            # flag one unbiased configuration in 20 by chance, and +0.5 with −0.5 is no bias
            # (helper 88). An interval that is not a number (null: unknown) flags nothing.
            outside = [r["bias"] for r in rs
                       if is_number(r["bias_ci95"]) and abs(r["bias"]) > r["bias_ci95"]]
            if (len(rs) >= 2 and len(outside) == len(rs)
                    and len({math.copysign(1, x) for x in outside}) == 1):
                b += " ‡"
                flagged.append(f"{c} at {spp} spp")
        summary.append((c, spp, len(rs), e, sd, t, eff, z, b))

    figures = []
    # The error plots have log axes: an error of 0 (a run equal to the reference) or a time of 0
    # has no place on them; the table still shows it.
    plotted = [s for s in summary if s[3] > 0 and s[5] > 0]
    left_out = len(summary) - len(plotted) if error else 0
    if error and plotted:
        fig, ax = plt.subplots(figsize=(7, 5))
        pts = [(s[5], s[3]) for s in plotted]
        for c in configs:
            xs = [s[5] for s in plotted if s[0] == c]
            ys = [s[3] for s in plotted if s[0] == c]
            ax.plot(xs, ys, "o-", label=c)
        front = pareto(pts)
        ax.plot([pts[i][0] for i in front], [pts[i][1] for i in front], "k--", lw=1,
                label="Pareto front")
        ax.scatter([pts[i][0] for i in front], [pts[i][1] for i in front], s=90,
                   facecolors="none", edgecolors="k")
        ax.set_xscale("log"), ax.set_yscale("log")
        ax.set_xlabel(time_label), ax.set_ylabel(error)
        ax.set_title(f"{error} vs time (mean over repeats)")
        ax.legend(fontsize=7), ax.grid(True, which="both", alpha=0.3)
        fig.tight_layout()
        save(fig, os.path.join(directory, "error_vs_time.png"))
        figures.append(("error_vs_time.png", f"{error} vs time; circled: the Pareto front"))

        fig, ax = plt.subplots(figsize=(7, 5))
        for c in configs:
            ss = [s for s in plotted if s[0] == c]
            ax.errorbar([s[1] for s in ss], [s[3] for s in ss], yerr=[s[4] for s in ss],
                        fmt="o-", capsize=3, label=c)
        spps = sorted({s[1] for s in plotted})
        if len(spps) > 1:  # (a relative MSE falls as 1/spp, an RMSE or a MAE as 1/√spp)
            e0 = min(s[3] for s in plotted if s[1] == spps[0])
            power = 1 if error == "relmse" else 0.5
            ax.plot(spps, [e0 * (spps[0] / n) ** power for n in spps], "k:",
                    label="∝ 1/spp" if power == 1 else "∝ 1/√spp")
        ax.set_xscale("log"), ax.set_yscale("log")
        ax.set_xlabel("samples per pixel"), ax.set_ylabel(error)
        ax.legend(fontsize=7), ax.grid(True, which="both", alpha=0.3)
        fig.tight_layout()
        save(fig, os.path.join(directory, "error_vs_spp.png"))
        figures.append(("error_vs_spp.png", f"{error} vs spp (bars: standard deviation over "
                                            "repeats)"))

    for a in axes + ["spp"]:
        vals = {}
        for r in rows:
            vals.setdefault(value_text(r.get(a)), []).append(
                r[time_key])
        keys = list(vals)
        fig, ax = plt.subplots(figsize=(7, 4))
        ax.bar(range(len(keys)), [mean_sd(vals[k])[0] for k in keys],
               yerr=[mean_sd(vals[k])[1] for k in keys], capsize=3)
        ax.set_xticks(range(len(keys)))
        ax.set_xticklabels([k if len(k) < 40 else k[:37] + "..." for k in keys], rotation=30,
                           ha="right", fontsize=7)
        ax.set_ylabel(time_label), ax.set_title(f"time vs {a}")
        fig.tight_layout()
        # (ASCII letters and digits kept, every other byte "_": as shvol batch's check of its
        # outputs, reportOutputs, names them.)
        name = "time_vs_" + "".join(chr(b) if chr(b).isalnum() and b < 128 else "_"
                                    for b in a.encode("utf-8")) + ".png"
        save(fig, os.path.join(directory, name))
        figures.append((name, f"mean {time_label} for each value of {a} (all other axes "
                              "pooled)"))

    # (No error column without an error metric: it was empty in every row; helper 159.)
    head = ["configuration", "spp", "runs"] + ([f"{error} (mean ± sd)"] if error else []) + [
        "time (s)"] + (
        ["1/(MSE·time)"] if efficient else []) + (["z-test passed"] if ztest else []) + (
            ["bias (mean)"] if biased_col else [])
    table = [head]
    for c, spp, n, e, sd, t, eff, z, b in summary:
        table.append([c, str(spp), str(n)] +
                     ([f"{e:.4g} ± {sd:.2g}" if n > 1 else f"{e:.4g}"] if error else []) +
                     [f"{t:.3g}"] + ([f"{eff:.4g}" if not math.isnan(eff) else ""] if efficient else []) +
                     ([z] if ztest else []) + ([b] if biased_col else []))
    summary = (f"{counted(len(rows), 'run')}, {counted(len(configs), 'configuration')}; "
               f"error metric: {error or 'none'}; time: {time_key} ({time_label}).")
    if not efficient:
        summary += (" No efficiency 1/(MSE·time) column: it needs the sweep's rmse metric" +
                    ("." if error else ", which needs a reference (no error metric here)."))
    if cut_short:  # (said nowhere before: the report was one run short; helper 141)
        summary += (f" Line {cut_short} of results.jsonl, cut short by a batch stopped while "
                    f"writing it, is left out: the next start of the batch renders that run again.")
    if left_out:
        summary += (f" Left out of the error plots (log axes): {counted(left_out, 'row')} of "
                    f"the table with an error or a time of 0.")
    if flagged:
        summary += (f" ‡ Biased against the reference (every repeat's bias outside its 95% "
                    f"interval, on one side, over two repeats or more): {'; '.join(flagged)}. A biased configuration's error levels off at "
                    f"its bias as samples grow: 1/(MSE·time) ranks fairly between unbiased "
                    f"configurations only.")
    if unreliable:
        summary += (f" § Fewer than {ZTEST_RELIABLE_SPP} samples per pixel: the standard errors "
                    f"the z-test divides by come from too few samples, and unbiased runs fail it "
                    f"there; it needs {ZTEST_RELIABLE_SPP} spp or more, and a few hundred where "
                    f"samples have heavy tails: {'; '.join(unreliable)}.")
    md = [f"# Batch report: {directory}", "", summary, ""]
    for f, caption in figures:
        md += [f"![{caption}]({f})", "", f"*{caption}*", ""]
    md.append("| " + " | ".join(head) + " |")
    md.append("|" + "---|" * len(head))
    md += ["| " + " | ".join(md_cell(x) for x in r) + " |" for r in table[1:]]
    write(os.path.join(directory, "report.md"), "\n".join(md) + "\n")

    body = [f"<h1>Batch report</h1><p>{html.escape(directory)}: {html.escape(summary)}</p>"]
    for f, caption in figures:
        body.append(f'<figure><img src="{f}"><figcaption>{html.escape(caption)}</figcaption>'
                    "</figure>")
    body.append("<table border=1 cellpadding=4>")
    for i, r in enumerate(table):
        tag = "th" if i == 0 else "td"
        body.append("<tr>" + "".join(f"<{tag}>{html.escape(x)}</{tag}>" for x in r) + "</tr>")
    body.append("</table>")
    write(os.path.join(directory, "report.html"),
          "<!doctype html><meta charset=utf-8><title>shvol batch report</title>\n"
          + "\n".join(body) + "\n")
    # Every file checked before the first is written: a directory named report.md was found
    # after the plots had been written.
    for path, _ in pending:
        problem = output_problem(path)
        if problem:
            fail(f"{path}: cannot write: {problem}")
    replace_together(pending)
    plt.close("all")
    # On stderr, as every command names what it wrote (it went to stdout, also under batch
    # --quiet; helper 139).
    if sys.argv[3] != "--quiet":
        plots = len(pending) - 2
        print(f"report: wrote {os.path.join(directory, 'report.md')}, report.html and {plots} "
              f"plot{'' if plots == 1 else 's'} beside them", file=sys.stderr)
    stop_if_signalled()  # (one that came during the renames: the report is whole)


pending = []  # (path, write_to(tmp)) of every output, written once all are made


def output_problem(path):
    """Why path cannot be written, as far as can be told before writing it (shvol's
    outputFileProblem, in short), or None."""
    if os.path.isdir(path):
        return "is a directory"
    if os.path.lexists(path) and not os.path.isfile(path):
        return "is not a regular file"
    parent = os.path.dirname(path) or "."
    if not os.access(parent, os.W_OK):
        return f"directory {parent} is not writable"
    return None


def replace_together(outputs):
    """Each write_to(tmp) of outputs [(path, write_to)], then every tmp renamed to its path: the
    report is replaced whole or not at all (each output was renamed as soon as it was written,
    so a full disk or a Ctrl-C part-way left new plots beside the last report; helper 100), and
    no temporary is left. A signal stops it before the renames, not during them."""
    temporaries = []
    try:
        for path, write_to in outputs:
            stop_if_signalled()
            temporaries.append(path + ".tmp")
            try:
                write_to(temporaries[-1])
            except OSError as e:
                fail(f"{path}: cannot write ({e.strerror or e})")
        stop_if_signalled()
        for k, ((path, _), tmp) in enumerate(zip(outputs, temporaries)):
            try:
                os.replace(tmp, path)
            except OSError as e:  # (only here are some outputs new and others old: said)
                done = ", ".join(os.path.basename(p) for p, _ in outputs[:k])
                fail(f"{path}: cannot write ({e.strerror or e})"
                     + (f"; {done} already replaced" if done else ""))
    finally:
        for tmp in temporaries:
            if os.path.lexists(tmp) and not os.path.isdir(tmp):
                os.remove(tmp)


def write(path, text):
    def to(tmp):
        with open(tmp, "w") as f:
            f.write(text)
    pending.append((path, to))


def save(fig, path):
    """A figure as a PNG."""
    stop_if_signalled()
    pending.append((path, lambda tmp: fig.savefig(tmp, dpi=110, format="png")))


if __name__ == "__main__":
    try:
        main()
    except Interrupted as e:  # no traceback, and 128 + the signal as shvol's commands exit with
        sys.exit(128 + e.number)
