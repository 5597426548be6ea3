"""read_event_log: XES (streamed), CSV and event DataFrames; ordering, labels, errors by case."""

import gzip

import numpy as np
import pandas as pd
import pytest

from bsi_sklearn.io import EventLog, read_event_log

HEAD = ('<?xml version="1.0" encoding="UTF-8"?>\n'
        '<log xes.version="1.0" xmlns="http://www.xes-standard.org/">\n'
        '<global scope="event"><string key="concept:name" value="DEFAULT"/></global>\n'
        '<string key="concept:name" value="the log"/>\n')


def event(act, ts=None, **attrs):
    inner = f'<string key="concept:name" value="{act}"/>'
    if ts is not None:
        inner += f'<date key="time:timestamp" value="{ts}"/>'
    for key, (tag, value) in attrs.items():
        inner += f'<{tag} key="{key}" value="{value}"/>'
    return f"<event>{inner}</event>"


def trace(case, events, **attrs):
    head = "" if case is None else f'<string key="concept:name" value="{case}"/>'
    for key, (tag, value) in attrs.items():
        head += f'<{tag} key="{key}" value="{value}"/>'
    return f"<trace>{head}{''.join(events)}</trace>\n"


def write_xes(path, traces):
    path.write_text(HEAD + "".join(traces) + "</log>\n", encoding="utf-8")
    return path


TYPED = trace("c1", [
    event("pay", "2024-01-02T10:00:00.000+01:00", n=("int", 3), cost=("float", 2.5),
          urgent=("boolean", "true"), resource=("string", "ann"), ref=("id", "x-1"),
          due=("date", "2024-02-01T00:00:00Z")),
    event("order", "2024-01-01T10:00:00.000+01:00", n=("int", 4), cost=("float", 1e3),
          urgent=("boolean", "false"), resource=("string", "bob"), ref=("id", "x-2"),
          due=("date", "2024-03-01T00:00:00Z")),
], ok=("boolean", "true"), region=("string", "north"))


def test_xes_every_attribute_type_and_time_order(tmp_path):
    path = write_xes(tmp_path / "log.xes", [TYPED, trace("c2", [event("order")],
                                                         ok=("boolean", "false"))])
    log = read_event_log(path, label="ok")
    assert isinstance(log, EventLog)
    cases, y, ids = log
    assert ids.tolist() == ["c1", "c2"] and y.tolist() == [1, 0]
    c1 = cases[0]
    assert list(c1.columns) == ["concept:name", "time:timestamp", "n", "cost", "urgent",
                                "resource", "ref", "due"]
    assert c1["concept:name"].tolist() == ["order", "pay"]  # sorted by time
    assert c1["n"].tolist() == [4, 3] and c1["cost"].tolist() == [1000.0, 2.5]
    assert c1["urgent"].tolist() == [False, True]
    assert c1["resource"].tolist() == ["bob", "ann"] and c1["ref"].tolist() == ["x-2", "x-1"]
    assert c1["due"].iloc[0] == pd.Timestamp("2024-03-01", tz="UTC")
    assert c1["time:timestamp"].iloc[0] == pd.Timestamp("2024-01-01T09:00", tz="UTC")
    assert list(c1.index) == [0, 1]
    # the case without timestamps keeps the file's order; case attributes are not events'
    assert cases[1]["time:timestamp"].isna().all()
    assert "region" not in c1.columns and "ok" not in c1.columns


def test_xes_gz_reads_the_same(tmp_path):
    plain = write_xes(tmp_path / "log.xes", [TYPED])
    packed = tmp_path / "log.xes.gz"
    packed.write_bytes(gzip.compress(plain.read_bytes()))
    a, b = read_event_log(plain), read_event_log(packed)
    pd.testing.assert_frame_equal(a.cases[0], b.cases[0])
    assert a.y is None and b.y is None


def test_nested_attributes_are_not_events_attributes(tmp_path):
    nested = ('<event><string key="concept:name" value="a"><string key="meta" value="m"/>'
              '</string><list key="l"><values><int key="x" value="1"/></values></list>'
              '</event>')
    cases, _, _ = read_event_log(write_xes(tmp_path / "l.xes", [trace("c", [nested])]))
    assert list(cases[0].columns) == ["concept:name"]
    assert cases[0]["concept:name"].tolist() == ["a"]


def test_stable_sort_keeps_ties_in_file_order(tmp_path):
    t = "2024-01-01T10:00:00Z"
    path = write_xes(tmp_path / "l.xes", [trace("c", [
        event("b", "2024-01-01T11:00:00Z"), event("x", t), event("y", t), event("z", t)])])
    assert read_event_log(path).cases[0]["concept:name"].tolist() == ["x", "y", "z", "b"]


@pytest.mark.parametrize("traces, message", [
    ([trace("c1", [event("a")]), trace("c2", [])],
     "case 'c2' has no events"),
    ([trace("c1", [event("a")]), trace("c1", [event("b")])],
     "two traces have the case id 'c1'"),
    ([trace("c1", [event("a", "2024-01-01T00:00:00Z"), event("b")])],
     "case 'c1', event 1 has no timestamp (column 'time:timestamp')"),
    ([trace("c1", [event("a", "yesterday")])],
     "case 'c1', event 0 has the date 'yesterday'"),
    ([trace("c1", [event("a", n=("int", "1.5"))])],
     "event attribute 'n': case 'c1', event 0 has the int '1.5'"),
    ([trace("c1", [event("a"), '<event><int key="n" value="1"/></event>'])],
     "case 'c1', event 1 has no activity (column 'concept:name')"),
    ([trace("c0", [event("a")]), trace(None, [event("a")])],
     "trace 1 (counted from 0) has no 'concept:name'"),
])
def test_xes_errors_name_the_case(tmp_path, traces, message):
    path = write_xes(tmp_path / "bad.xes", traces)
    with pytest.raises(ValueError) as exc:
        read_event_log(path)
    assert message in str(exc.value) and "bad.xes" in str(exc.value)


def test_malformed_xml_names_the_line(tmp_path):
    path = tmp_path / "broken.xes"
    path.write_text(HEAD + "<trace><event></trace>\n</log>\n")
    with pytest.raises(ValueError, match=r"broken.xes: not well-formed XES \(XML\) at line 5"):
        read_event_log(path)


@pytest.mark.parametrize("labels, pos_label, message", [
    (["yes", None], "yes", "case 'c2' has no label"),
    (["yes", "no", "maybe"], "yes", "case 'c3' has a third label value 'maybe'"),
    (["yes", "no"], None, "case 'c1' has the label 'yes'; labels must be 0/1"),
    (["yes", "no"], "si", "pos_label='si' is not among the labels ['yes', 'no']"),
])
def test_label_errors_name_the_case(tmp_path, labels, pos_label, message):
    traces = [trace(f"c{i + 1}", [event("a")],
                    **({} if lab is None else {"out": ("string", lab)}))
              for i, lab in enumerate(labels)]
    with pytest.raises(ValueError) as exc:
        read_event_log(write_xes(tmp_path / "l.xes", traces), label="out",
                       pos_label=pos_label)
    assert message in str(exc.value)


def test_pos_label_as_text_matches_typed_labels(tmp_path):
    traces = [trace("a", [event("x")], out=("int", 1)), trace("b", [event("x")],
                                                              out=("int", 2))]
    path = write_xes(tmp_path / "l.xes", traces)
    assert read_event_log(path, label="out", pos_label="1").y.tolist() == [1, 0]
    assert read_event_log(path, label="case:out", pos_label=2).y.tolist() == [0, 1]


# ------------------------------------------------------------------ CSV and DataFrames
FRAME = pd.DataFrame({
    "case:concept:name": ["c1", "c2", "c1", "c2", "c3"],
    "concept:name": ["pay", "order", "order", "ship", "order"],
    "time:timestamp": ["2024-01-02T10:00:00", "2024-01-01T08:00:00", "2024-01-01T10:00:00",
                       "2024-01-03T10:00:00", "2024-01-01T10:00:00"],
    "org:resource": ["ann", "bob", "ann", "cid", "bob"],
    "case:ok": [1, 0, 1, 0, 1],
})


def as_xes(tmp_path):
    by_case = {}
    for row in FRAME.itertuples(index=False):
        ts = row[2] + "Z"
        by_case.setdefault(row[0], ([], row[4]))[0].append(
            event(row[1], ts, **{"org:resource": ("string", row[3])}))
    traces = [trace(c, evs, ok=("int", ok)) for c, (evs, ok) in by_case.items()]
    return write_xes(tmp_path / "same.xes", traces)


def test_xes_csv_and_dataframe_agree(tmp_path):
    csv = tmp_path / "log.csv"
    FRAME.to_csv(csv, index=False)
    readings = [read_event_log(FRAME, label="ok"), read_event_log(csv, label="ok"),
                read_event_log(as_xes(tmp_path), label="ok")]
    for cases, y, ids in readings:
        assert ids.tolist() == ["c1", "c2", "c3"] and y.tolist() == [1, 0, 1]
        assert [c["concept:name"].tolist() for c in cases] == [
            ["order", "pay"], ["order", "ship"], ["order"]]
        assert [c["org:resource"].tolist() for c in cases] == [
            ["ann", "ann"], ["bob", "cid"], ["bob"]]
        assert list(cases[0].columns) == ["concept:name", "time:timestamp", "org:resource"]
    # the XES dates carry an offset (UTC); the CSV's are naive: same instants, same order
    assert readings[2].cases[0]["time:timestamp"].dt.tz is not None


def test_custom_column_names_and_label_table(tmp_path):
    df = FRAME.rename(columns={"case:concept:name": "id", "concept:name": "act",
                               "time:timestamp": "when"}).drop(columns="case:ok")
    table = pd.Series({"c1": "good", "c2": "bad", "c3": "good"})
    cases, y, ids = read_event_log(df, case_id="id", activity="act", timestamp="when",
                                   labels=table, pos_label="good")
    assert y.tolist() == [1, 0, 1]
    assert list(cases[1].columns) == ["concept:name", "time:timestamp", "org:resource"]
    path = tmp_path / "labels.csv"
    pd.DataFrame({"id": ["c3", "c1", "c2"], "y": [1, 1, 0]}).to_csv(path, index=False)
    assert read_event_log(df, case_id="id", activity="act", timestamp="when",
                          labels=path).y.tolist() == [1, 0, 1]
    with pytest.raises(ValueError, match="case 'c3' has no label in the labels table"):
        read_event_log(df, case_id="id", activity="act", labels={"c1": 1, "c2": 0})
    with pytest.raises(ValueError, match=r"the case id\(s\) \['c9'\] are not cases"):
        read_event_log(df, case_id="id", activity="act",
                       labels={"c1": 1, "c2": 0, "c3": 1, "c9": 1})


@pytest.mark.parametrize("change, kwargs, message", [
    ({"case:ok": [1, 0, 0, 0, 1]}, {"label": "ok"},
     "case 'c1', event 0 has the label 1 in column 'case:ok', but event 1 of the case has "
     "0"),
    ({"case:ok": [1, 0, 1, None, 1]}, {"label": "ok"},
     "case 'c2', event 1 has no label (column 'case:ok')"),
    ({"concept:name": ["pay", None, "order", "ship", "order"]}, {},
     "case 'c2', event 0 has no activity (column 'concept:name')"),
    ({"time:timestamp": ["2024-01-02", "noon", "2024-01-01", "2024-01-03", "2024-01-01"]},
     {}, "case 'c2', event 0 has the timestamp 'noon' (column 'time:timestamp')"),
    ({"time:timestamp": ["2024-01-02", None, "2024-01-01", "2024-01-03", "2024-01-01"]},
     {}, "case 'c2', event 0 has no timestamp"),
    ({}, {"label": "missing"}, "no label column 'missing'"),
    ({}, {"timestamp": "when"}, "no timestamp column 'when'"),
    ({}, {"pos_label": 1}, "pos_label is given but no label"),
])
def test_frame_errors_name_the_case_and_column(change, kwargs, message):
    df = FRAME.assign(**change)
    with pytest.raises(ValueError) as exc:
        read_event_log(df, **kwargs)
    assert message in str(exc.value)


def test_ragged_csv_rows_are_reported_by_line(tmp_path):
    path = tmp_path / "log.csv"
    path.write_text("case:concept:name,concept:name,time:timestamp,case:ok\n"
                    "c1,order,2024-01-01T10:00:00,1\nc1,ship\n"
                    "c2,order,2024-01-01T10:00:00,0\n")
    # not "event 1 has no timestamp": the row lost its last two fields
    with pytest.raises(ValueError, match=f"{path}, line 3: the row has 2 fields, the header "
                                         "has 4"):
        read_event_log(path, label="ok")
    labels = tmp_path / "labels.csv"
    labels.write_text("case:concept:name,ok\nc1,1\nc2\n")
    good = tmp_path / "good.csv"
    FRAME.drop(columns="case:ok").to_csv(good, index=False)
    with pytest.raises(ValueError, match=f"labels {labels}, line 3: the row has 1 field, "):
        read_event_log(good, labels=labels)


def test_numeric_timestamps_and_no_timestamps():
    df = FRAME.drop(columns="time:timestamp").assign(step=[2, 1, 1, 2, 1])
    cases, _, _ = read_event_log(df, timestamp="step")
    assert cases[0]["concept:name"].tolist() == ["order", "pay"]
    cases, _, _ = read_event_log(FRAME.drop(columns="time:timestamp"))
    assert cases[0]["concept:name"].tolist() == ["pay", "order"]  # the file's order
    assert "time:timestamp" not in cases[0].columns


def test_labels_already_boolean_need_no_pos_label():
    y = read_event_log(FRAME.assign(**{"case:ok": [True, False, True, False, True]}),
                       label="ok").y
    assert y.dtype.kind == "i" and y.tolist() == [1, 0, 1]
    np.testing.assert_array_equal(read_event_log(FRAME, label="case:ok").y, [1, 0, 1])


def test_reading_restores_the_garbage_collector(tmp_path):
    import gc

    path = write_xes(tmp_path / "l.xes", [trace("c", [event("a")])])
    assert gc.isenabled()
    read_event_log(path)
    assert gc.isenabled()
    with pytest.raises(ValueError):
        read_event_log(write_xes(tmp_path / "bad.xes", [trace("c", [])]))
    assert gc.isenabled()
    gc.disable()
    try:
        read_event_log(path)
        assert not gc.isenabled()
    finally:
        gc.enable()
