"""The pandas DataFrame entry: `identify(frame, umin, umax, u=..., y=...)` and `diagnose(frame,
...)`, the sample time from a time column or a datetime/timedelta index."""

import numpy as np
import pandas as pd
import pytest

import hsid

PAPER = dict(refine=False, segments=7, f=10, p=10)


@pytest.fixture(scope="module")
def arrays_model(record):
    _, u, y = record
    return hsid.identify(u, y, -1.0, 1.0, ts=0.01, **PAPER)


def test_a_frame_with_a_time_column(record, arrays_model):
    _, u, y = record
    df = pd.DataFrame({"t": 0.01 * np.arange(len(u)), "u": u, "y": y})
    model = hsid.identify(df, -1.0, 1.0, **PAPER)
    assert model == arrays_model and model.ts == pytest.approx(0.01, rel=1e-12)
    assert hsid.from_frame(df, -1.0, 1.0, **PAPER) == arrays_model


def test_named_columns_and_a_timedelta_index(record, arrays_model):
    _, u, y = record
    index = pd.to_timedelta(np.arange(len(u)) * 10, unit="ms")
    df = pd.DataFrame({"volts": u, "deg": y}, index=index)
    model = hsid.identify(df, umin=-1.0, umax=1.0, u="volts", y="deg", **PAPER)
    assert model == arrays_model
    dated = df.set_index(pd.Timestamp("2026-01-01") + index)
    assert hsid.identify(dated, -1.0, 1.0, u="volts", y="deg", **PAPER) == arrays_model


def test_without_time_the_given_ts(record, arrays_model):
    _, u, y = record
    df = pd.DataFrame({"u": u, "y": y})
    assert hsid.identify(df, -1.0, 1.0, ts=0.01, **PAPER) == arrays_model
    assert hsid.identify(df, -1.0, 1.0, **PAPER).ts is None


def test_bad_frames_are_typed_errors(record):
    _, u, y = record
    df = pd.DataFrame({"t": 0.01 * np.arange(len(u)), "u": u, "y": y})
    with pytest.raises(hsid.SettingsError) as e:
        hsid.identify(df, -1.0, 1.0, ts=0.02, **PAPER)
    assert e.value.kind == "sample_time" and "column 't'" in str(e.value)
    with pytest.raises(hsid.DataError) as e:
        hsid.identify(df, -1.0, 1.0, y="output", **PAPER)
    assert e.value.kind == "missing_column" and "'output'" in str(e.value)
    jumpy = df.copy()
    jumpy.loc[100:, "t"] += 0.005  # one step of 0.015 s; the mean step moves by 0.0008 %
    with pytest.raises(hsid.DataError) as e:
        hsid.identify(jumpy, -1.0, 1.0, **PAPER)
    assert e.value.kind == "time_not_uniform" and "column 't'[100]" in str(e.value), str(e.value)
    backwards = df.iloc[::-1]
    with pytest.raises(hsid.DataError) as e:
        hsid.identify(backwards, -1.0, 1.0, **PAPER)
    assert e.value.kind == "time_not_increasing"


def test_diagnose_takes_a_frame(record):
    _, u, y = record
    df = pd.DataFrame({"t": 0.01 * np.arange(len(u)), "u": u, "y": y})
    report = hsid.diagnose(df, -1.0, 1.0)
    plain = hsid.diagnose(u, y, -1.0, 1.0)
    assert report.pop("ts") == pytest.approx(0.01, rel=1e-12)
    assert report == plain
