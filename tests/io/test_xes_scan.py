"""The vectorised XES scanner reads exactly what the expat reader reads, or steps aside."""

import gzip
import io

import numpy as np
import pandas as pd
import pytest

from bsi_sklearn.io._xes import read_xes_columns
from bsi_sklearn.io._xes_scan import Unsure, scan_xes

DECL = '<?xml version="1.0" encoding="UTF-8"?>\n'
LOG = '<log xes.version="1.0" xmlns="http://www.xes-standard.org/">\n'
HEAD = (DECL + "<!-- a comment before the root -->\n" + LOG
        + '<extension name="Concept" prefix="concept" uri="http://x.org/c.xesext"/>\n'
        + '<global scope="trace"><string key="concept:name" value="__INVALID__"/></global>\n'
        + '<classifier name="Activity" keys="concept:name"/>\n'
        + '<string key="concept:name" value="the log"/>\n')

DOCS = {
    "plain": HEAD + (
        '<trace><string key="concept:name" value="c1"/><boolean key="ok" value="true"/>'
        '<event><string key="concept:name" value="a"/>'
        '<date key="time:timestamp" value="2024-01-01T10:00:00.000+01:00"/>'
        '<int key="n" value="3"/><float key="x" value="2.5"/><id key="r" value="i-1"/>'
        '<boolean key="b" value="0"/></event>\n'
        '<event><string key="concept:name" value="b"/><int key="n" value="-4"/></event>'
        '</trace>\n'
        '<trace><string key="concept:name" value="c2"/>'
        '<event><string key="concept:name" value="c"/><float key="x" value="1e3"/></event>'
        '</trace>\n</log>\n'),
    "entities, quotes, order, whitespace": DECL + LOG + (
        "<trace>\n  <string value='c&amp;1' key=\"concept:name\" />\n"
        '<event\n><string\tkey="concept:name"\n   value="a &lt;b&gt; &quot;q&quot; &apos;s&apos;'
        ' &#65;&#x42;&#x20AC;"/>\n'
        "<string key='resource' value='tab\there\nnew\r\nline'/>"
        '<string key="plain" value="it\'s &#10;&#13; kept"/></event >\n'
        '<event><string key = "concept:name" value = "b"/><string key="plain" '
        "value='\"'/></event>\n</trace >\n</log>\n"),
    "comments and nested attributes": HEAD + (
        "<trace><!-- a comment in a trace -->"
        '<string key="concept:name" value="c1"><string key="meta" value="m"/></string>'
        '<list key="l"><values><int key="x" value="1"/></values></list>'
        '<container key="ct"><string key="inner" value="v"/></container>'
        '<event><!-- event comment --><string key="concept:name" value="a">'
        '<int key="meta" value="2"/></string><list key="z"/></event>'
        '<event><string key="concept:name" value="b"/></event></trace></log>'),
    "non-ascii and missing values": HEAD + (
        '<trace><string key="concept:name" value="cäse"/>'
        '<event><string key="concept:name" value="größe €"/><int key="n" value="1"/></event>'
        '<event><string key="concept:name" value="日本"/></event>'
        '<event><string key="concept:name" value="x"/><int key="n" value="2"/>'
        '<string key="n2" value=""/></event></trace>\r\n</log>\r\n'),
    "mixed types and log-level attributes": DECL + LOG + (
        '<string key="k" value="log level"/><int key="k2" value="9"/>'
        '<trace><string key="concept:name" value="c1"/>'
        '<event><string key="concept:name" value="a"/><int key="v" value="1"/></event>'
        '<event><string key="concept:name" value="b"/><string key="v" value="two"/></event>'
        '</trace><trace><string key="concept:name" value="c2"/><int key="v" value="5"/>'
        '<event><string key="concept:name" value="a"/></event></trace></log>'),
    "pretty-printed, as pm4py and ProM write": DECL + LOG.replace(">", ">\n") + (
        '\t<trace>\n\t\t<string key="concept:name" value="c1" />\n'
        '\t\t<event>\n\t\t\t<string key="concept:name" value="a" />\n'
        '\t\t\t<date key="time:timestamp" value="2024-01-01T00:00:00+00:00" />\n'
        '\t\t</event>\n\t\t<event>\n\t\t\t<string key="concept:name" value="b"/>\n'
        '\t\t\t<int key="n"  value="1" />\n\t\t</event>\n\t</trace>\n</log>\n'),
    "no declaration, prefixed tags": (
        '<xes:log xmlns:xes="http://www.xes-standard.org/">'
        '<xes:trace><xes:string key="concept:name" value="c1"/>'
        '<xes:event><xes:string key="concept:name" value="a"/></xes:event>'
        '<xes:event><xes:string key="concept:name" value="b"/></xes:event></xes:trace>'
        '</xes:log>'),
}


def write(tmp_path, text, name="log.xes"):
    path = tmp_path / name
    path.write_bytes(text.encode("utf-8"))
    return path


def assert_same(a, b):
    pd.testing.assert_frame_equal(a.events, b.events)
    assert a.n_traces == b.n_traces
    assert list(a.traces) == list(b.traces)
    for key in a.traces:
        assert [str(v) for v in a.traces[key]] == [str(v) for v in b.traces[key]], key


@pytest.mark.parametrize("doc", list(DOCS))
@pytest.mark.parametrize("chunk", [None, 1, 7, 64])
def test_scanner_reads_what_expat_reads(tmp_path, doc, chunk):
    text = DOCS[doc]
    path = write(tmp_path, text)
    with open(path, "rb") as fh:
        scan_xes(fh, chunk or 1 << 20)  # the fast path takes it (no Unsure)
    fast = read_xes_columns(path, fast=True, chunk=chunk)
    slow = read_xes_columns(path, fast=False)
    assert_same(fast, slow)
    assert len(fast.events) > 0


def test_scanner_reads_entities_and_normalises_whitespace(tmp_path):
    cols = read_xes_columns(write(tmp_path, DOCS["entities, quotes, order, whitespace"]),
                            chunk=3)
    ev = cols.events
    assert cols.traces["concept:name"] == ["c&1"]
    assert ev["concept:name"].tolist() == ['a <b> "q" \'s\' AB€', "b"]
    assert ev["resource"].iloc[0] == "tab here new line"
    assert ev["plain"].tolist() == ["it's \n\r kept", '"']


def test_scanner_gzip_and_every_chunk_boundary(tmp_path):
    text = DOCS["plain"]
    packed = tmp_path / "log.xes.gz"
    packed.write_bytes(gzip.compress(text.encode()))
    slow = read_xes_columns(write(tmp_path, text), fast=False)
    assert_same(read_xes_columns(packed), slow)
    for chunk in range(1, 40):
        assert_same(read_xes_columns(packed, chunk=chunk), slow)


def test_scanner_errors_match_expat(tmp_path):
    empty = HEAD + ('<trace><string key="concept:name" value="c1"/>'
                    '<event><string key="concept:name" value="a"/></event></trace>'
                    '<trace><string key="concept:name" value="c2"/></trace></log>')
    path = write(tmp_path, empty)
    with open(path, "rb") as fh:
        scan_xes(fh)
    messages = []
    for fast in (True, False):
        with pytest.raises(ValueError) as exc:
            read_xes_columns(path, fast=fast)
        messages.append(str(exc.value))
    assert messages[0] == messages[1] and "trace 'c2' has no events" in messages[0]
    stray = (DECL + LOG + '<event><string key="concept:name" value="a"/></event></log>')
    path = write(tmp_path, stray, "stray.xes")
    for fast in (True, False):
        with pytest.raises(ValueError, match="event 0 .* is not directly inside a <trace>"):
            read_xes_columns(path, fast=fast)


@pytest.mark.parametrize("text", [
    # CDATA and a DOCTYPE with its own entity: the scanner steps aside, expat reads them
    HEAD + '<trace><string key="concept:name" value="c1"/><event><![CDATA[x]]>'
    '<string key="concept:name" value="a"/></event></trace></log>',
    DECL + '<!DOCTYPE log [<!ENTITY who "ann">]>' + LOG
    + '<trace><string key="concept:name" value="c1"/><event>'
    '<string key="concept:name" value="&who;"/></event></trace></log>',
    HEAD + '<trace><string key="concept:name" value="a>b"/><event>'
    '<string key="concept:name" value="a"/></event></trace></log>',
    HEAD + '<trace><string key="concept:name" value="c"/><?pi x?><event>'
    '<string key="concept:name" value="a"/></event></trace></log>',
])
def test_what_the_scanner_cannot_vouch_for_falls_back(tmp_path, text):
    path = write(tmp_path, text)
    with open(path, "rb") as fh, pytest.raises(Unsure):
        scan_xes(fh)
    assert_same(read_xes_columns(path), read_xes_columns(path, fast=False))


def test_doctype_entity_is_read_by_the_fallback(tmp_path):
    text = (DECL + '<!DOCTYPE log [<!ENTITY who "ann">]>' + LOG
            + '<trace><string key="concept:name" value="c1"/><event>'
            '<string key="concept:name" value="&who;"/></event></trace></log>')
    cols = read_xes_columns(write(tmp_path, text))
    assert cols.events["concept:name"].tolist() == ["ann"]


@pytest.mark.parametrize("text", [
    HEAD + "<trace><event></trace></log>",                        # mismatched
    HEAD + '<trace><event a="1" a="2"></event></trace></log>',   # duplicate attribute
    HEAD + '<trace><string key="k" value="a & b"/></trace></log>',  # bare &
    HEAD + '<trace><string key="k" value="&nbsp;"/></trace></log>',  # undefined entity
    HEAD + '<trace><string key="k" value="&#1;"/></trace></log>',  # invalid character
    HEAD + "<trace></trace></log><log></log>",                    # two roots
    HEAD + "<trace>text</trace></log>",                           # text
    HEAD + "<trace></trace>",                                     # unclosed root
    HEAD + "<trace></trace></log>\x01",                           # control character
])
def test_malformed_or_unusual_xml_is_left_to_expat(tmp_path, text):
    with pytest.raises(Unsure):
        scan_xes(io.BytesIO(text.encode("utf-8")))


def test_scanner_on_a_larger_log_matches_expat(tmp_path):
    rnd = np.random.default_rng(0)
    parts = [HEAD]
    for c in range(300):
        parts.append(f'<trace><string key="concept:name" value="c{c}"/>'
                     f'<boolean key="ok" value="{"true" if c % 2 else "false"}"/>\n')
        for e in range(int(rnd.integers(1, 6))):
            extra = f'<float key="f" value="{rnd.random():.3f}"/>' if rnd.random() < .5 else ""
            parts.append(f'<event><string key="concept:name" value="a{rnd.integers(9)}"/>'
                         f'<date key="time:timestamp" value="2024-01-01T00:{e:02d}:00Z"/>'
                         f'{extra}</event>\n')
        parts.append("</trace>\n")
    path = write(tmp_path, "".join(parts) + "</log>\n")
    slow = read_xes_columns(path, fast=False)
    for chunk in (None, 100, 997):
        assert_same(read_xes_columns(path, chunk=chunk), slow)


def unusual(n):
    events = "".join(f"<event><string value='a{i}' key='concept:name'/></event>"
                     for i in range(n))
    return DECL + LOG + f'<trace><string key="concept:name" value="c"/>{events}</trace></log>'


def test_a_log_of_mostly_unusual_tags_is_left_to_expat(tmp_path):
    path = write(tmp_path, unusual(1200))
    with open(path, "rb") as fh, pytest.raises(Unsure):
        scan_xes(fh)
    cols = read_xes_columns(path)
    assert cols.events["concept:name"].tolist() == [f"a{i}" for i in range(1200)]
    with open(write(tmp_path, unusual(200), "few.xes"), "rb") as fh:
        scan_xes(fh)  # a few hundred such tags: the scanner reads them one by one


VALUES = ["a", "b c", "x&amp;y", "&lt;t&gt;", "q&quot;", "ä€", "", "1", "&#65;", "tab\tx",
          "l\nm", "it's"]


KEYS = ["concept:name", "k1", "k2", "org:resource", "time:timestamp"]


TAG_OF = {"concept:name": "string", "k1": "int", "k2": "boolean", "org:resource": "id",
          "time:timestamp": "date"}


def random_attribute(rnd, key, mix):
    tag = rnd.choice(["string", "int", "float", "boolean", "date", "id"]) if mix \
        else TAG_OF[key]
    value = {"int": str(rnd.randint(-5, 5)), "float": f"{rnd.random():.2f}",
             "boolean": rnd.choice(["true", "false"]),
             "date": f"2024-01-0{rnd.randint(1, 9)}T00:00:00Z"}.get(tag, rnd.choice(VALUES))
    q = '"' if "'" in value else rnd.choice(['"', '"', "'"])
    ws = rnd.choice([" ", " ", "\n ", "\t"])
    pair = [f"key={q}{key}{q}", f"value={q}{value}{q}"]
    if rnd.random() < .2:
        pair.reverse()
    if rnd.random() < .1:
        return f'<{tag}{ws}{ws.join(pair)}><string key="meta" value="m"/></{tag}>'
    return f"<{tag} {ws.join(pair)}{rnd.choice(['/>', '/>', ' />'])}"


def random_log(rnd):
    parts, mix = [HEAD], rnd.random() < .3  # mix: keys of several types (read as strings)
    for c in range(rnd.randint(1, 30)):
        parts.append(f'<trace><string key="concept:name" value="c{c}"/>'
                     + "".join(random_attribute(rnd, key, mix)
                               for key in rnd.sample(KEYS[1:], rnd.randint(0, 2))))
        for _ in range(rnd.randint(1, 5)):
            parts.append("<event>" + "".join(random_attribute(rnd, key, mix)
                                             for key in rnd.sample(KEYS, rnd.randint(0, 4)))
                         + ("<!-- c -->" if rnd.random() < .1 else "") + "</event>\n")
        parts.append("</trace>\n")
    return "".join(parts) + "</log>"


@pytest.mark.parametrize("seed", range(25))
def test_random_logs_read_the_same_by_both(tmp_path, seed):
    import random

    rnd = random.Random(seed)
    path = write(tmp_path, random_log(rnd))
    with open(path, "rb") as fh:
        scan_xes(fh, rnd.choice([5, 50, 1 << 20]))
    results = []
    for fast, chunk in ((True, rnd.choice([3, 17, None])), (False, None)):
        try:
            results.append(read_xes_columns(path, fast=fast, chunk=chunk))
        except ValueError as exc:  # a key given twice in an event: the same message
            results.append(str(exc))
    if isinstance(results[0], str) or isinstance(results[1], str):
        assert results[0] == results[1]
    else:
        assert_same(*results)
