"""`hsid.read_csv`: hsid's own CSV files read by the host library's reader, as the command line
reads them: columns, the `# ts` comment and time column, the unit comments."""

import subprocess

import numpy as np
import pytest

import hsid
from conftest import HOLD, cli_model

UNITS = {"input": "V", "output": "deg"}


def test_a_simulated_record_gives_its_arrays_sample_time_and_units(record):
    path, u, y = record
    rec = hsid.read_csv(path)
    assert np.array_equal(rec.u, u) and np.array_equal(rec.y, y)
    assert rec.ts == 0.01 and rec.units == UNITS and rec.t is None
    assert rec.u.dtype == np.float64
    # str paths work as pathlib ones do.
    assert np.array_equal(hsid.read_csv(str(path)).y, y)


def test_the_record_identifies_as_the_command_line_does(record, cli, tmp_path):
    path, _, _ = record
    # The command line takes ts and units from the header comments: the model files agree.
    model = hsid.read_csv(path).identify(-1.0, 1.0, refine=False, segments=7, f=10, p=10)
    text = cli_model(cli, tmp_path, path, "--no-refine", "--segments", "7", "--f", "10", "--p", "10")
    assert model.to_json() == text
    assert model.ts == 0.01 and model.units == UNITS


def test_an_excitation_file_has_no_output(cli, tmp_path):
    out = subprocess.run(
        [cli, "excite", "--umin", "-2", "--umax", "3", "--samples", "700", "--hold", "100", "--seed", "4"],
        check=True, capture_output=True,
    ).stdout
    path = tmp_path / "u.csv"
    path.write_bytes(out)
    rec = hsid.read_csv(path)
    assert np.array_equal(rec.u, hsid.excite(-2.0, 3.0, 700, hold=100, seed=4))
    assert rec.y is None and rec.ts is None and rec.units is None
    with pytest.raises(hsid.DataError) as e:
        rec.identify(-2.0, 3.0)
    assert e.value.kind == "missing_column"


def test_a_time_column_gives_the_sample_time(tmp_path):
    path = tmp_path / "t.csv"
    t = 0.02 * np.arange(50)
    rows = "\n".join(f"{float(ti)!r};{i % 7 / 7!r};{i!r}" for i, ti in enumerate(t))
    path.write_text("# ts = 0.02 s\nt;u;y\n" + rows + "\n")
    rec = hsid.read_csv(path)
    assert rec.ts == pytest.approx(0.02, rel=1e-12)
    assert np.array_equal(rec.t, t) and np.array_equal(rec.y, np.arange(50.0))
    assert rec.units is None
    # A comment that disagrees with the column is refused, naming both.
    path.write_text("# ts = 0.01 s\nt;u;y\n" + rows + "\n")
    with pytest.raises(hsid.DataError) as e:
        hsid.read_csv(path)
    assert e.value.kind == "sample_time" and "0.01" in str(e.value), str(e.value)


def test_bad_files_are_typed_errors(tmp_path):
    path = tmp_path / "r.csv"
    path.write_text("t,u,y\n0,0,0\n1,0,0\n3,0,0\n")
    with pytest.raises(hsid.DataError) as e:
        hsid.read_csv(path)
    assert e.value.kind == "time_not_uniform" and "line 3" in str(e.value), str(e.value)
    path.write_text("a,b\n1,2\n")
    with pytest.raises(hsid.DataError) as e:
        hsid.read_csv(path)
    assert e.value.kind == "missing_column" and "u" in str(e.value)
    path.write_text("u,y\n1,2\n")
    with pytest.raises(hsid.DataError) as e:
        hsid.read_csv(path, y="output")
    assert e.value.kind == "missing_column"
    with pytest.raises(hsid.DataError) as e:
        hsid.read_csv(tmp_path / "absent.csv")
    assert e.value.kind == "csv_file"
    path.write_text("# input unit = V\nu,y\n1,2\n")
    with pytest.raises(hsid.DataError) as e:
        hsid.read_csv(path)
    assert e.value.kind == "units"
    with pytest.raises(hsid.SettingsError) as e:
        hsid.read_csv(path, delimiter="|")
    assert e.value.kind == "delimiter"


def test_named_columns(tmp_path):
    path = tmp_path / "r.csv"
    path.write_text("volts,deg,time\n-1,0.5,0\n1,0.25,0.5\n0,0.125,1\n")
    rec = hsid.read_csv(path, u="volts", y="deg", time="time")
    assert list(rec.u) == [-1.0, 1.0, 0.0] and list(rec.y) == [0.5, 0.25, 0.125]
    assert rec.ts == 0.5
