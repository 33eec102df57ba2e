"""The Python module against the truth, the real files and the command
line: same numbers, same options, same messages."""
import filecmp
import json
import os
import pathlib
import runpy
import shutil
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import wearscar

ROOT = pathlib.Path(__file__).resolve().parents[2]
SAMPLES = ROOT / "samples" / "data"
SHARED = pathlib.Path(os.environ.get("WEARSCAR_SHARED_DATA",
                                     ROOT.parent / "shared" / "data"))
BINARY = os.environ.get("WEARSCAR_BINARY", "")


def small(case="B-RT-R", **options):
    settings = dict(cycles=60, rate=1000, scan_cols=256, scan_rows=192,
                    scan_pitch=0.0296, seed=5)
    settings.update(options)
    return wearscar.simulate(case, **settings)


def test_the_notebook_example_recovers_mu_within_its_noise(capsys):
    runpy.run_path(os.environ.get(
        "WEARSCAR_EXAMPLES", ROOT / "python" / "examples") +
        "/fit_simulated_test.py")
    out = capsys.readouterr().out
    assert "explained by wear-scar interaction" in out
    # The example prints the mean of mu-hat and of the truth: equal within
    # 0.003 at the calibrated noise (noise 1).
    line = next(l for l in out.splitlines() if l.startswith("mu-hat (k from P)"))
    mean = float(line.split("mean ")[1].split(",")[0])
    truth = float(line.split("truth ")[1].split(",")[0])
    assert abs(mean - truth) < 0.003, line


def test_fuse_recovers_the_simulated_mu_per_cycle():
    test = small()
    result = wearscar.fuse(test.force, test.scan, running_in=20)
    truth = np.array(test.truth["mu_per_cycle"])
    cycles = result.cycles
    assert cycles["cycle"][0] == 1 and cycles["cycle"][-1] == 60
    # Counts as integers, measures as floats.
    assert cycles["cycle"].dtype == np.int64
    assert cycles["running_in"].dtype == np.int64
    assert cycles["mu_hat_force"].dtype == np.float64
    steady = cycles["cycle"] > 20
    assert np.abs(cycles["mu_hat_force"][steady] - truth[steady]).max() < 0.01
    assert abs(result.mu_hat_scan - truth[steady].mean()) < 0.005
    assert result.explained
    # Error bars: each cycle's interval around its mu-hat, the test's mean
    # inside its 95% interval, which the keyword option leaves to the scan.
    low, high = cycles["mu_hat_force_low"], cycles["mu_hat_force_high"]
    assert np.all(low < cycles["mu_hat_force"])
    assert np.all(cycles["mu_hat_force"] < high)
    lo, hi = result.summary["comparison"]["mu_hat_force"]["interval95"]
    assert lo < result.summary["comparison"]["mu_hat_force"]["mean"] < hi
    # An analysis unit's table and section come through as the others do:
    # the scanned shape grew during this record (the simulator's groove
    # starts from nothing), about whole over the compared cycles.
    shape = result.tables["scan_shape_history"]
    assert list(shape["cycle"]) == list(cycles["cycle"])
    section = result.summary["scan_shape_history"]
    assert section["first_cycles_factor"] < 0.5
    assert abs(section["compared_cycles_factor"] - 1) < 0.1
    assert "scan_shape_history" in [u["kind"] for u in result.summary["units"]]
    history = wearscar.fuse(test.force, test.scan, running_in=20,
                            scan_slope_history=True)
    assert history.summary["options"]["scan"]["scan_slope_history"] is True
    # Plain values for a notebook's json.dump.
    json.dumps(result.to_dict())


def test_a_coulomb_test_made_of_numpy_arrays_gives_its_mu():
    # Flat track (P constant, k = 0): Q = s mu P exactly, mu = 0.23.
    t = np.arange(0, 30, 1 / 1000.0)
    x = 2.85 * np.sin(2 * np.pi * t)
    v = np.gradient(x, t)
    p = np.full_like(t, 30.0)
    q = np.sign(v) * 0.23 * p
    record = wearscar.ForceRecord(t, x, q, p)
    assert len(record) == t.size
    result = wearscar.fuse(record, running_in=2, no_lugre=True)
    assert result.mu_hat == pytest.approx(0.23, abs=1e-3)
    # The headline's mu, quoted with k from P.
    assert result.mu_to_quote == pytest.approx(0.23, abs=1e-3)
    assert result.summary["headline"].startswith(
        "mu = {:.4f}".format(result.mu_to_quote))
    assert result.no_mu_to_quote_because == ""
    with pytest.raises(KeyError, match="no table .summary.*it has .*cycles"):
        result.frame("summary")
    with pytest.raises(wearscar.OptionError, match="one length"):
        wearscar.ForceRecord(t, x[:-1], q, p)


def test_read_force_gives_arrays_in_mm_n_s():
    record = wearscar.read_force(SAMPLES / "B-RT-R.force.csv")
    assert record.x_mm.dtype == np.float64
    # 20 cycles at 500 Hz (the bundled samples are small).
    assert len(record) == record.time_s.size == 10500
    assert np.diff(record.time_s).mean() == pytest.approx(0.002)
    assert record.x_mm.max() == pytest.approx(2.85, abs=0.01)
    assert record.p_n.mean() == pytest.approx(30.0, abs=0.3)
    assert record.metadata["units"] == ["s", "mm", "N", "N"]
    # Options by the command line's names: the x column read in um is a
    # 0.0057 mm stroke, refused as implausible.
    with pytest.raises(wearscar.ForceError, match="check the x unit"):
        wearscar.read_force(SAMPLES / "B-RT-R.force.csv", x_unit="um")
    metres = wearscar.read_force(SAMPLES / "B-RT-R.force.csv",
                                 columns="x=x_mm:mm", force_unit="N")
    assert np.array_equal(metres.x_mm, record.x_mm)


@pytest.mark.skipif(not (SHARED / "other" / "plu-1.plu").exists(),
                    reason="../shared/data (real instrument files) is absent")
def test_read_scan_reads_a_real_sensofar_file_to_its_reference():
    scan = wearscar.read_scan(SHARED / "other" / "plu-1.plu")
    assert scan.shape == (576, 768)
    assert scan.height_mm.dtype == np.float32
    assert scan.shape[1] * scan.dx_mm == pytest.approx(1.274880066, abs=1e-8)
    # rms 2.834391 um (the file's reference value).
    z = scan.height_mm.astype(np.float64)
    assert np.sqrt(np.nanmean((z - np.nanmean(z)) ** 2)) == pytest.approx(
        2.834391e-3, abs=2e-9)
    assert scan.metadata["instrument"] == "Sensofar"


def test_errors_carry_the_command_lines_messages(tmp_path):
    bad = tmp_path / "bad.csv"
    rows = [f"{i / 1000},{i % 7},{'abc' if i == 10 else 1.5},30"
            for i in range(20)]
    bad.write_text("time_s,x_mm,Q_N,P_N\n" + "\n".join(rows) + "\n")
    with pytest.raises(wearscar.ForceError) as error:
        wearscar.read_force(bad)
    assert str(error.value) == (
        f"{bad}: line 12, column 3 ('Q'): found 'abc', expected a number")
    with pytest.raises(wearscar.OptionError) as error:
        wearscar.fuse(SAMPLES / "B-RT-R.force.csv", spring=0)
    # The keyword by its Python name, the command line's message after it.
    assert str(error.value) == (
        "fuse(spring=...): found 0; expected a number from 1e-06 to 1e+06")
    with pytest.raises(TypeError) as error:
        wearscar.fuse(SAMPLES / "B-RT-R.force.csv", sprung=10)
    assert str(error.value) == ("fuse() got an unexpected keyword argument "
                                "'sprung'; did you mean 'spring'?")
    with pytest.raises(wearscar.OptionError, match=r"k_estimate=\.\.\."):
        wearscar.fuse(SAMPLES / "B-RT-R.force.csv", k_estimate="median")
    # Two values for a setting that takes one are refused, not the last
    # silently used; what is neither a path nor a record is a TypeError.
    with pytest.raises(wearscar.OptionError) as error:
        wearscar.fuse(SAMPLES / "B-RT-R.force.csv", running_in=[5, 7])
    assert str(error.value) == (
        "fuse(running_in=...): given 2 values (5, 7); it takes one")
    with pytest.raises(TypeError, match=r"fuse\(force=\.\.\.\): expected a "
                       r"path or a ForceRecord; found int"):
        wearscar.fuse(42)
    with pytest.raises(TypeError, match=r"fuse\(scan=\.\.\.\): .*found list"):
        wearscar.fuse(SAMPLES / "B-RT-R.force.csv", [1, 2])
    assert "keyword argument with a bad value" in wearscar.OptionError.__doc__
    # Every public function, class and method says what it does.
    import inspect
    undocumented = []
    for name in dir(wearscar):
        item = getattr(wearscar, name)
        if name.startswith("_") or inspect.ismodule(item) or not callable(item):
            continue
        if not (item.__doc__ or "").strip():
            undocumented.append(name)
        if inspect.isclass(item):
            undocumented += [name + "." + m for m, v in vars(item).items()
                             if not m.startswith("_") and callable(v)
                             and not (getattr(v, "__doc__", "") or "").strip()]
    assert undocumented == []
    if BINARY:
        for args, call in (
                (["force", str(bad)], lambda: wearscar.read_force(bad)),
                (["fuse", str(SAMPLES / "B-RT-R.force.csv"), "--running-in",
                  "x"], lambda: wearscar.fuse(SAMPLES / "B-RT-R.force.csv",
                                               running_in="x"))):
            cli = subprocess.run([BINARY] + args, capture_output=True,
                                 text=True)
            assert cli.returncode == 2
            with pytest.raises(ValueError) as error:
                call()
            assert cli.stderr.strip().endswith(str(error.value).split(": ", 1)[-1])


def test_defaults_are_the_command_lines():
    result = wearscar.fuse(SAMPLES / "B-RT-R.force.csv",
                           SAMPLES / "B-RT-R.scan.gsf")
    options = result.summary["options"]
    assert options["spring_n_per_mm"] == 10.19
    assert options["k_estimate"] == "ensemble"
    assert options["slope"] == "both"
    assert options["scan"]["level_order"] == 1
    changed = wearscar.fuse(SAMPLES / "B-RT-R.force.csv", spring=8.5,
                            k_estimate="cycle", running_in=5,
                            slope="force").summary["options"]
    assert changed["spring_n_per_mm"] == 8.5
    assert changed["k_estimate"] == "cycle"
    assert changed["running_in_cycles"] == 5
    assert changed["slope"] == "force"


@pytest.mark.skipif(not BINARY, reason="WEARSCAR_BINARY not given")
def test_result_write_gives_the_files_of_wearscar_fuse(tmp_path, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1700000000")
    force = str(SAMPLES / "S-RL-R.force.csv")
    scan = str(SAMPLES / "S-RL-R.scan.gsf")
    # With its figures (4: gnuplot missing), so with the loop viewer's data;
    # the figures are not among the files compared.
    cli = subprocess.run([BINARY, "fuse", force, "--scan", scan,
                          "--running-in", "5", "-o", str(tmp_path / "cli")],
                         capture_output=True)
    assert cli.returncode in (0, 4), cli.stderr
    result = wearscar.fuse(force, scan, running_in=5)
    written = result.write(tmp_path / "py")
    names = sorted(pathlib.Path(p).name for p in written)
    assert "result.json" in names and "profiles.csv" in names
    assert "loop_viewer.json" in names
    match, mismatch, errors = filecmp.cmpfiles(tmp_path / "cli",
                                               tmp_path / "py", names,
                                               shallow=False)
    assert mismatch == [] and errors == []
    assert not result.explained  # S-RL-R: the elastic part


@pytest.mark.skipif(not BINARY or not shutil.which("gnuplot"),
                    reason="WEARSCAR_BINARY not given or gnuplot missing")
def test_result_write_draws_the_figures_of_wearscar_fuse(tmp_path):
    force = str(SAMPLES / "B-RT-R.force.csv")
    scan = str(SAMPLES / "B-RT-R.scan.gsf")
    subprocess.run([BINARY, "fuse", force, "--scan", scan, "--running-in",
                    "5", "--figure-format", "svg,png", "-o",
                    str(tmp_path / "cli")],
                   check=True, capture_output=True)
    result = wearscar.fuse(force, scan, running_in=5)
    written = result.write(tmp_path / "py", figures="svg,png")
    figures = sorted(pathlib.Path(p).name for p in written
                     if p.endswith((".png", ".svg")))
    by_command = sorted(p.name for p in (tmp_path / "cli").iterdir()
                        if p.suffix in (".png", ".svg"))
    assert figures == by_command and len(figures) == 30  # 15 figures
    for name in figures:
        head = (tmp_path / "py" / name).read_bytes()[:5]
        assert head == (b"\x89PNG\r" if name.endswith(".png") else b"<?xml")
    # figures=True: the command's default, SVG alone.
    svg = result.write(tmp_path / "svg", figures=True)
    assert sum(p.endswith(".svg") for p in svg) == 15
    assert not any(p.endswith(".png") for p in svg)
    with pytest.raises(wearscar.OptionError, match="expected svg, png"):
        result.write(tmp_path / "bad", figures="jpeg")
    # Without figures, none is drawn.
    plain = result.write(tmp_path / "plain")
    assert not any(p.endswith(".png") for p in plain)


def test_audit_of_the_bundled_samples(tmp_path):
    rows = wearscar.audit(SAMPLES, out=tmp_path, jobs=2, running_in=5,
                          compare_cycles=15)
    assert len(rows) == 12
    by_name = {row["specimen"]: row for row in rows}
    assert by_name["B-RT-R"]["species"] == "beech"
    assert not by_name["S-RL-R"]["verdict"]["explained"]
    assert by_name["B-RT-R"]["verdict"]["explained"]
    # The number to quote: none for the flagged case, with the reason; the
    # explained one's is its headline's mu.
    flagged = by_name["S-RL-R"]["quote"]
    assert flagged["status"] == "not explained" and flagged["mu"] is None
    assert "not explained" in flagged["reason"]
    quoted = by_name["B-RT-R"]["quote"]
    assert quoted["status"] in ("explained", "not settled")
    assert "mu = {:.4f}".format(quoted["mu"]) in by_name["B-RT-R"]["headline"]
    summary = (tmp_path / "summary.csv").read_text().splitlines()
    header = summary[0].split(",")
    at = header.index("mu_to_quote")
    assert header[at - 1] == "status"
    cells = {line.split(",")[0]: line.split(",") for line in summary[1:]}
    assert cells["S-RL-R"][at] == "" and cells["S-RL-R"][at - 1] == \
        "not explained"
    assert float(cells["B-RT-R"][at]) == pytest.approx(quoted["mu"], abs=1e-6)
    # Integers as integers: a file's size in bytes.
    assert cells["B-RT-R"][header.index("force_bytes")].isdigit()
    # The groups over the specimens with a mu to quote: the species' means
    # are their specimens' means; S-RL-R, not explained, is left out.
    mu = [g for g in rows.groups if g["quantity"] == "mu_to_quote"][0]
    spruce = [lv for lv in mu["levels"] if lv["factor"] == "species" and
              lv["level"] == "spruce"][0]
    spruce_mus = [r["quote"]["mu"] for r in rows
                  if r["species"] == "spruce" and r["quote"]["mu"] is not None]
    assert spruce["specimens"] == len(spruce_mus) == 5
    assert spruce["mean"] == pytest.approx(sum(spruce_mus) / 5, abs=1e-12)
    assert any(item.startswith("S-RL-R") for item in mu["left_out"])
    with pytest.raises(KeyError, match="it has summary, groups, differences"):
        rows.frame("summery")
    # The workbooks read back: the summary's header and numbers as numbers.
    openpyxl = pytest.importorskip("openpyxl")
    book = openpyxl.load_workbook(tmp_path / "summary.xlsx", read_only=True)
    sheet = list(book["summary"].iter_rows(values_only=True))
    assert list(sheet[0]) == header
    by_row = {r[0]: r for r in sheet[1:]}
    assert by_row["B-RT-R"][at] == pytest.approx(quoted["mu"], abs=1e-6)
    assert by_row["S-RL-R"][at] is None
    assert isinstance(by_row["B-RT-R"][header.index("force_bytes")], int)
    groups = openpyxl.load_workbook(tmp_path / "groups.xlsx", read_only=True)
    assert groups.sheetnames == ["groups", "differences"]
    levels = list(groups["groups"].iter_rows(values_only=True))
    row = [r for r in levels if r[:3] == ("mu_to_quote", "species", "spruce")]
    assert row and row[0][3] == 5 and row[0][4] == pytest.approx(
        spruce["mean"], abs=1e-6)
    # The tables as frames (pandas).
    pytest.importorskip("pandas")
    frame = rows.frame("summary")
    assert list(frame["specimen"]) == [r["specimen"] for r in rows]
    assert set(rows.frame("groups")["factor"]) >= {"species", "plane"}
    assert (tmp_path / "summary.csv").read_text().count("\n") == 13
    assert (tmp_path / "summary.jsonl").read_text().count("\n") == 12
    assert (tmp_path / "B-RT-R" / "cycles.csv").exists()
    # The report as `wearscar audit --no-figures` writes it: the flagged
    # specimen highlighted, no figure.
    report = (tmp_path / "report.html").read_text()
    assert report.count('<tr class="flagged">') == 1
    assert "data:image/png" not in report
    assert not (tmp_path / "B-RT-R" / "fig13_mu_hat.png").exists()
    assert not (tmp_path / "B-RT-R" / "loop_viewer.json").exists()
    # Without `out`, the same rows and nothing written.
    again = wearscar.audit(SAMPLES, jobs=2, running_in=5, compare_cycles=15)
    assert [r["comparison"]["mu_hat_force"]["mean"] for r in again] == \
        [r["comparison"]["mu_hat_force"]["mean"] for r in rows]


def test_an_audit_in_memory_warns_as_the_command_does(tmp_path):
    # A copy of one specimen's force file beside it, without a scan: its
    # row and the original's name each other, and the copy's says that its
    # scan is missing while others have one, as `wearscar audit` writes.
    for suffix in (".force.csv", ".scan.gsf"):
        shutil.copy(SAMPLES / ("B-RT-R" + suffix), tmp_path / ("B-RT-R" + suffix))
    shutil.copy(SAMPLES / "B-RT-R.force.csv", tmp_path / "B-RL-R.force.csv")
    rows = {r["specimen"]: r for r in wearscar.audit(tmp_path, jobs=2)}
    copy, original = rows["B-RL-R"]["warnings"], rows["B-RT-R"]["warnings"]
    assert any("force file is byte-identical to that of B-RT-R" in w for w in copy)
    assert any("force file is byte-identical to that of B-RL-R" in w for w in original)
    assert any(w.startswith("no scan paired, although other specimens") for w in copy)
    assert not any("scan file is byte-identical" in w for w in original)


def test_long_calls_release_the_gil():
    # Deterministic: with a switch interval far longer than the call, a
    # thread that holds the GIL through fuse lets no other Python run
    # between its two clock readings around the call; the main thread,
    # sleeping between its stamps, stamps inside that span only if the
    # call released the GIL.
    test = small(cycles=300, rate=2000)
    span = []

    def call():
        t0 = time.perf_counter()
        wearscar.fuse(test.force, test.scan)
        span.extend([t0, time.perf_counter()])

    interval = sys.getswitchinterval()
    sys.setswitchinterval(100.0)
    try:
        worker = threading.Thread(target=call)
        stamps = []
        worker.start()
        while worker.is_alive():
            stamps.append(time.perf_counter())
            time.sleep(1e-4)
        worker.join()
    finally:
        sys.setswitchinterval(interval)
    inside = [t for t in stamps if span[0] < t < span[1]]
    assert inside, (len(stamps), span)


def test_simulate_takes_effects_and_lists_of_cases():
    runs = small(["B-RT-R", "S-TL-L"], cycles=20)
    assert [r.case for r in runs] == ["B-RT-R", "S-TL-L"]
    hidden = small(effect="ploughing=1.0", cycles=20)
    assert hidden.truth["effects"]["ploughing_n_per_mm"] == 1.0
    # Plain values all the way down (a notebook's json.dump).
    plain = json.loads(json.dumps(runs[0].to_dict(), allow_nan=True))
    assert len(plain["force"]["x_mm"]) == len(runs[0].force)
    assert len(plain["scan"]["height_mm"]) == runs[0].scan.shape[0]
    with pytest.raises(wearscar.OptionError, match="simulate"):
        small("X-RT-R")


def test_python_conventions_missing_files_per_cycle_values_and_the_api(tmp_path):
    # A missing file is FileNotFoundError (an OSError), naming the path,
    # for each way a path enters.
    missing = tmp_path / "nope.csv"
    for call in (lambda: wearscar.read_force(missing),
                 lambda: wearscar.read_scan(missing),
                 lambda: wearscar.fuse(missing),
                 lambda: wearscar.audit(tmp_path / "no-folder")):
        with pytest.raises(FileNotFoundError) as e:
            call()
        assert "nope.csv" in str(e.value) or "no-folder" in str(e.value)
    # mu-hat per cycle, named so, beside the steady value.
    test = small(cycles=30)
    result = wearscar.fuse(test.force, test.scan, running_in=5, no_lugre=True)
    per_cycle = result.mu_hat_per_cycle
    assert isinstance(per_cycle, np.ndarray) and len(per_cycle) == 30
    assert np.array_equal(per_cycle, result.cycles["mu_hat_force"])
    assert abs(np.mean(per_cycle[5:]) - result.mu_hat) < 0.01
    # A keyword's error names it as Python spells it; a misspelt one gets
    # the closest.
    with pytest.raises(wearscar.OptionError, match=r"fuse\(spring=\.\.\.\)"):
        wearscar.fuse(test.force, spring=-1)
    with pytest.raises(TypeError, match="did you mean 'running_in'"):
        wearscar.fuse(test.force, runing_in=5)
    # The module's names are its API (and private ones).
    public = {n for n in dir(wearscar) if not n.startswith("_")}
    assert public == set(wearscar.__all__) - {"__version__"}, public


def test_result_frame_is_a_dataframe_when_pandas_is_there():
    test = small(cycles=20)
    result = wearscar.fuse(test.force, no_lugre=True)
    try:
        import pandas  # noqa: F401
    except ImportError:
        with pytest.raises(ImportError, match="python3-pandas"):
            result.frame()
        return
    frame = result.frame("cycles")
    assert list(frame["cycle"]) == list(range(1, 21))
    assert np.allclose(frame["mu_hat_force"], result.mu_hat_per_cycle,
                       equal_nan=True)


def test_watch_yields_each_cycle_of_a_file_being_written(tmp_path):
    test = small("B-RT-R", cycles=40, rate=500)
    f = test.force
    path = tmp_path / "running.csv"
    rows = np.column_stack([f.time_s, f.x_mm, f.q_n, f.p_n])

    def write():
        # The software's blocks: a header, then 0.2 s of the test every
        # 20 ms, each cut inside a row (the rest follows with the next).
        text = "time_s,x_mm,Q_N,P_N\n" + "".join(
            "{:.6f},{:.6f},{:.5f},{:.5f}\n".format(*r) for r in rows)
        with open(path, "w") as out:
            step = len(text) // 200
            for at in range(0, len(text), step):
                out.write(text[at:at + step])
                out.flush()
                time.sleep(0.02)

    writer = threading.Thread(target=write)
    writer.start()
    seen = list(wearscar.watch(path, poll=0.05, idle=1.5))
    writer.join()
    cycles = [c for c in seen if c["cycle"] is not None]
    assert [c["cycle"] for c in cycles] == list(range(1, len(cycles) + 1))
    whole = wearscar.fuse(path)
    assert len(cycles) == len(whole.mu_hat_per_cycle)
    assert seen[-1]["cycle"] is None
    assert [e["kind"] for e in seen[-1]["events"]][-1] == "idle"
    # mu-hat with k from P over each cycle and those before it: the mean
    # after cycle 10 within 0.002 of the whole test's (centred ensemble).
    live = np.mean([c["mu_hat"] for c in cycles[10:]])
    assert abs(live - np.nanmean(whole.mu_hat_per_cycle[10:])) < 0.002
    events = [e["kind"] for c in seen for e in c["events"]]
    assert "verdict" in events
    # B-RT-R is explained: good news, not a warning; the writer stopping
    # is not good news.
    verdict = next(e for c in seen for e in c["events"] if e["kind"] == "verdict")
    assert "not explained" not in verdict["message"]
    assert verdict["good"] is True
    assert seen[-1]["events"][-1]["good"] is False


def test_watch_follows_a_file_per_block_as_one_test(tmp_path):
    # The software starts a file per block (run_1 .. run_4), each with its
    # header, its clock continuing; watch(folder, pattern=...) reports the
    # cycles of the whole test and says each block's turn.
    test = small("B-RT-R", cycles=40, rate=500)
    f = test.force
    rows = np.column_stack([f.time_s, f.x_mm, f.q_n, f.p_n])
    blocks = tmp_path / "blocks"
    blocks.mkdir()
    (blocks / "notes.txt").write_text("not a block\n")
    per = len(rows) // 4 + 1

    def write():
        for b in range(4):
            with open(blocks / "run_{}.csv".format(b + 1), "w") as out:
                out.write("time_s,x_mm,Q_N,P_N\n")
                for i, r in enumerate(rows[b * per:(b + 1) * per]):
                    out.write("{:.6f},{:.6f},{:.5f},{:.5f}\n".format(*r))
                    if i % 500 == 0:
                        out.flush()
                        time.sleep(0.02)
            time.sleep(0.2)

    writer = threading.Thread(target=write)
    writer.start()
    seen = list(wearscar.watch(blocks, pattern="run_*.csv", poll=0.05,
                               idle=1.5))
    writer.join()
    whole = tmp_path / "whole.csv"
    whole.write_text("".join((blocks / "run_{}.csv".format(b + 1)).read_text()
                             for b in range(4)))
    cycles = [c for c in seen if c["cycle"] is not None]
    assert [c["cycle"] for c in cycles] == list(range(1, len(cycles) + 1))
    assert len(cycles) == len(wearscar.fuse(whole).mu_hat_per_cycle)
    notes = [e["message"] for c in seen for e in c["events"]
             if e["kind"] == "block"]
    assert notes[0] == "block run_1.csv started"
    assert "block run_3.csv finished; block run_4.csv started" in notes
    assert not any(e["kind"] == "restart" for c in seen for e in c["events"])
    with pytest.raises(wearscar.ForceError, match="is not a folder"):
        next(wearscar.watch(whole, pattern="run_*.csv"))
    with pytest.raises(wearscar.OptionError, match="steady's hold"):
        next(wearscar.watch(whole, steady_cycles=10, steady_hold=20))
