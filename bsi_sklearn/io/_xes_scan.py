"""A vectorised XES scanner: the file's tags found and read with numpy, a chunk at a time.

The expat reader (``_xes.py``) pays a Python call per start and end tag; this one finds every
``<`` and ``>`` of a chunk with numpy, names each tag from a 16-byte window after its ``<``,
checks that the tags nest (open and close tags paired level by level), and reads the common
attribute element ``<string key="K" value="V"/>`` without a Python step per tag. Tags of any
other shape (attributes in another order, single quotes, entities, whitespace or newlines in
the tag, ``<log>`` / ``<extension>`` / ``<global>`` attributes) are read one by one with a
regular expression, as XML reads them (attribute-value normalisation, the five predefined
entities and character references).

Whatever it cannot be sure of raises :class:`Unsure`, and the caller reads the whole file
with expat instead: a ``>`` inside an attribute value or a comment, CDATA, a DOCTYPE,
processing instructions (other than the XML declaration), an encoding other than UTF-8,
text between tags, names of 16 bytes or more or outside ASCII, malformed XML (expat then
reports it with its line), a typed attribute without ``key`` or ``value``.
"""

from __future__ import annotations

import re

import numpy as np
import pandas as pd

__all__ = ["Unsure", "scan_xes"]

_TYPED = ("string", "id", "date", "int", "float", "boolean")
_NESTING = ("list", "container", "values")
_OTHER, _NEST, _EVENT, _TRACE = 0, 7, 8, 9  # tag codes; 1..6 are _TYPED
_OUT, _IN_EVENT, _IN_TRACE = 0, 1, 2  # where an attribute goes (the expat reader's `table`)
_W = 16  # name window: names of up to 15 bytes
CHUNK = 8 << 20


class Unsure(Exception):
    """The scanner cannot vouch for this file: read it with expat."""


def _lut(chars):
    table = np.zeros(256, dtype=bool)
    table[list(chars)] = True
    return table


_WS = b" \t\r\n"
_BAD = _lut(bytes([*range(0, 9), 11, 12, *range(14, 32)]))
_NAME = rb"[A-Za-z_:][A-Za-z0-9_:.-]*"
_NAME_RE = re.compile(_NAME + rb"\Z")
_NAME_END = re.compile(rb"[^ \t\r\n/>]*")
_KEY_WORD = int.from_bytes(b' key="', "little")
_VALUE_WORD = int.from_bytes(b'" value=', "little")
_ATTRS = re.compile(rb"(?:[ \t\r\n]+" + _NAME + rb"[ \t\r\n]*=[ \t\r\n]*"
                    rb"(?:\"[^\"<]*\"|'[^'<]*'))*[ \t\r\n]*\Z")
_ATTR = re.compile(rb"(" + _NAME + rb")[ \t\r\n]*=[ \t\r\n]*(?:\"([^\"<]*)\"|'([^'<]*)')")
_REF = re.compile(r"&(?:(amp|lt|gt|quot|apos)|#([0-9]+)|#x([0-9a-fA-F]+));")
_ENTITIES = {"amp": "&", "lt": "<", "gt": ">", "quot": '"', "apos": "'"}
_DECL = re.compile(rb"<\?xml[ \t\r\n]+version[ \t\r\n]*=[ \t\r\n]*(\"1\.[0-9]+\"|'1\.[0-9]+')"
                   rb"(?:[ \t\r\n]+encoding[ \t\r\n]*=[ \t\r\n]*(\"[A-Za-z][A-Za-z0-9._-]*\""
                   rb"|'[A-Za-z][A-Za-z0-9._-]*'))?"
                   rb"(?:[ \t\r\n]+standalone[ \t\r\n]*=[ \t\r\n]*(?:\"(?:yes|no)\""
                   rb"|'(?:yes|no)'))?[ \t\r\n]*\?>")
_COMMENT = re.compile(rb"<!--(.*)-->\Z", re.S)
_TEXT = re.compile(rb">[ \t\r\n]*[^ \t\r\n<]")


def _char(code):
    if code in (0x9, 0xA, 0xD) or 0x20 <= code <= 0xD7FF or 0xE000 <= code <= 0xFFFD \
            or 0x10000 <= code <= 0x10FFFF:
        return chr(code)
    raise Unsure  # expat: reference to invalid character number


def _value(raw):
    """An attribute value as XML reads it: whitespace normalised, references replaced."""
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise Unsure from None
    text = text.replace("\r\n", " ").replace("\r", " ").replace("\n", " ").replace("\t", " ")
    if "&" not in text:
        return text
    if text.count("&") != len(_REF.findall(text)):
        raise Unsure  # an undefined entity or a bare '&'

    def sub(m):
        if m.group(1):
            return _ENTITIES[m.group(1)]
        return _char(int(m.group(2)) if m.group(2) else int(m.group(3), 16))

    return _REF.sub(sub, text)


def _attributes(rest):
    """``{name: value}`` of the attribute text of a tag (after its name), or Unsure."""
    if not _ATTRS.match(rest):
        raise Unsure
    out = {}
    for name, dq, sq in _ATTR.findall(rest):
        if name in out:
            raise Unsure  # duplicate attribute
        out[name] = _value(dq if dq or not sq else sq)
    return out


def _low_bytes(k):
    """uint64 masks keeping the ``k`` (0..8) low bytes."""
    k = np.asarray(k, dtype=np.uint64)
    full = k >= 8
    mask = (np.uint64(1) << (np.uint64(8) * np.where(full, 0, k).astype(np.uint64))) \
        - np.uint64(1)
    return np.where(full, np.uint64(0xFFFFFFFFFFFFFFFF), mask)


def _ident(names):
    """The (n, 2) uint64 identity of names of up to 15 bytes, as the scanner computes it."""
    win = np.zeros((len(names), _W), dtype=np.uint8)
    for i, name in enumerate(names):
        if len(name) >= _W:
            raise Unsure
        win[i, :len(name)] = np.frombuffer(name, dtype=np.uint8)
    return win.view("<u8")


def _spans(a, starts, ends):
    """The byte spans ``a[s:e]`` (disjoint, increasing) decoded from UTF-8: a list of str."""
    if not len(starts):
        return []
    step = ends - starts + 1  # each span and its closing byte (a quote)
    offs = np.cumsum(step) - step
    idx = np.arange(int(offs[-1] + step[-1])) + np.repeat(starts - offs, step)
    buf = a[idx]
    buf[offs + step - 1] = 0  # the closing quotes become the separators
    try:
        text = buf.tobytes().decode("utf-8")
    except UnicodeDecodeError:
        raise Unsure from None
    return text.split("\x00")[:-1]


def _groups(inverse, n_groups):
    """Row positions of each code (in order), and each code's first row."""
    order = np.argsort(inverse, kind="stable")
    ends = np.cumsum(np.bincount(inverse, minlength=n_groups))
    return np.split(order, ends[:-1]), order[ends - np.diff(ends, prepend=0)]


def _keys(a, words, starts, ends):
    """The keys ``a[s:e]`` as codes (order of first appearance) and their texts."""
    lens = ends - starts
    if lens.max() > 24:
        inverse, uniq = pd.factorize(np.array(_spans(a, starts, ends), dtype=object))
        return inverse, list(uniq)
    w = [words[starts + 8 * i] & _low_bytes(np.clip(lens - 8 * i, 0, 8)) for i in range(3)]
    h = (w[0] * np.uint64(0x9E3779B97F4A7C15)) ^ (w[1] * np.uint64(0xC2B2AE3D27D4EB4F)) \
        ^ (w[2] * np.uint64(0x165667B19E3779F9)) ^ lens.astype(np.uint64)
    inverse, uniq = pd.factorize(h)
    _, first = _groups(inverse, len(uniq))
    rep = first[inverse]
    if not ((w[0] == w[0][rep]) & (w[1] == w[1][rep]) & (w[2] == w[2][rep])
            & (lens == lens[rep])).all():  # pragma: no cover - a hash collision
        inverse, uniq = pd.factorize(np.array(_spans(a, starts, ends), dtype=object))
        return inverse, list(uniq)
    try:
        return inverse, [a[s:e].tobytes().decode("utf-8")
                         for s, e in zip(starts[first].tolist(), ends[first].tolist())]
    except UnicodeDecodeError:
        raise Unsure from None


class _Key:
    __slots__ = ("owners", "values", "kind", "mixed")

    def __init__(self, kind):
        self.owners, self.values, self.kind, self.mixed = [], [], kind, False


class _Scanner:
    def __init__(self):
        self.stack = []  # identities (id0, id1) of the open elements
        self.root = None
        self.codes = None  # list of (id0, id1, code)
        self.attr_depth = 0  # open attribute elements (typed or nesting) enclosing here
        self.state = _OUT
        self.n_ev = self.n_tr = self.tr_start = 0
        self.stray = []
        self.counts = []
        self.events, self.traces = {}, {}

    # ------------------------------------------------------------------ one chunk
    def piece(self, data):
        a = np.frombuffer(data, dtype=np.uint8)
        ctrl = np.flatnonzero(a < 32)
        if len(ctrl) and _BAD[a[ctrl]].any():
            raise Unsure  # a control character: not XML
        if not data.isascii():
            try:
                text = data.decode("utf-8")
            except UnicodeDecodeError:
                raise Unsure from None
            if "\ufffe" in text or "\uffff" in text:
                raise Unsure
        lt = np.flatnonzero(a == 60)
        gt = np.flatnonzero(a == 62)
        if len(lt) != len(gt):
            raise Unsure
        if not len(lt):
            if data.strip(_WS):
                raise Unsure
            return
        if (gt < lt).any() or (lt[1:] < gt[:-1]).any():
            raise Unsure  # a '<' or '>' outside a tag's brackets: in a value, comment, text
        if data[:lt[0]].strip(_WS) or data[gt[-1] + 1:].strip(_WS) or _TEXT.search(data):
            raise Unsure  # text between elements
        b1 = a[lt + 1]
        special = (b1 == 33) | (b1 == 63)  # <! and <?
        if special.any():
            for i in np.flatnonzero(special):
                m = _COMMENT.match(data, int(lt[i]), int(gt[i]) + 1)
                if m is None or b"--" in m.group(1) or m.group(1).endswith(b"-"):
                    raise Unsure  # CDATA, DOCTYPE, a processing instruction
            keep = ~special
            lt, gt, b1 = lt[keep], gt[keep], b1[keep]
            if not len(lt):
                return
        close = b1 == 47
        self_ = (a[gt - 1] == 47) & ~close
        n = len(lt)
        ns = lt + 1 + close  # where each name starts
        rest_end = gt - self_
        # tags with a tab, newline, carriage return or '&' inside are read one by one
        odd = np.zeros(n, dtype=bool)
        amp = np.flatnonzero(a == 38)
        odd_pos = np.sort(np.concatenate([ctrl, amp])) if len(amp) else ctrl
        if len(odd_pos):
            j = np.searchsorted(lt, odd_pos, side="right") - 1
            ok = j >= 0
            j, p = j[ok], odd_pos[ok]
            odd[j[p < gt[j]]] = True
        spaces = np.append(np.flatnonzero(a == 32), len(a))
        ne = np.minimum(spaces[np.searchsorted(spaces, ns)], rest_end)  # where names end
        for i in np.flatnonzero(odd):
            ne[i] = _NAME_END.match(data, int(ns[i])).end()
        nl = ne - ns
        if not ((nl > 0) & (nl < _W)).all():
            raise Unsure  # an empty name, or one of 16 bytes or more
        pad = np.frombuffer(data + bytes(32), dtype=np.uint8)
        words = np.ndarray((len(pad) - 7,), dtype="<u8", buffer=pad, strides=(1,))
        ident = np.empty((n, 2), dtype=np.uint64)
        ident[:, 0] = words[ns] & _low_bytes(np.minimum(nl, 8))
        ident[:, 1] = words[ns + 8] & _low_bytes(np.maximum(nl - 8, 0))
        self._names(ident)
        code = self._code(ident)
        self._check_names(data, ident, code, ns, nl)

        # tags of the plain shape <name key="K" value="V"/> (or " />"); every other tag with
        # attributes is read by _attributes, one by one
        has_rest = rest_end > ne
        plain = has_rest & ~close & ~odd
        cand = np.flatnonzero(plain)
        q = np.flatnonzero(a == 34)
        qs = np.zeros(n, dtype=np.int64)
        if len(cand) and len(q) < 4:
            plain[cand] = False
        elif len(cand):
            # the first quote after the name, and the three after it: names hold no quotes
            qs[cand] = np.minimum(np.searchsorted(q, ne[cand]), len(q) - 4)
            base = qs[cand]
            q0, q1, q2, q3 = q[base], q[base + 1], q[base + 2], q[base + 3]
            good = np.ones(len(cand), dtype=bool)
            end = rest_end[cand]  # the closing quote, then '/>' or '>', or ' />' (pm4py)
            good &= (q0 == ne[cand] + 5) & (q2 == q1 + 8) & (
                (q3 + 1 == end) | ((q3 + 2 == end) & (a[np.minimum(q3 + 1, len(a) - 1)] == 32)))
            good &= q1 < q3  # q0 < q1 < q2 < q3 all inside the tag
            good &= words[ne[cand]] & _low_bytes(np.full(len(cand), 6)) == _KEY_WORD
            good &= words[q1] == _VALUE_WORD  # '" value=' and then the '"' at q2
            plain[cand[~good]] = False
        slow = np.flatnonzero(has_rest & ~plain)
        if len(slow) > 1000 and 5 * len(slow) > n:
            raise Unsure  # mostly tags of other shapes: expat reads those quicker
        slow_kv = {}
        for i in slow:
            rest = data[int(ne[i]):int(rest_end[i])]
            if close[i]:
                if rest.strip(_WS):
                    raise Unsure
                continue
            if not rest[:1].isspace():
                raise Unsure  # e.g. <a/b>
            attrs = _attributes(rest)
            if 1 <= code[i] <= 6:
                slow_kv[int(i)] = (attrs.get(b"key"), attrs.get(b"value"))

        # ---------------------------------------------------------- nesting
        delta = np.where(close, -1, np.where(self_, 0, 1)).astype(np.int64)
        before = len(self.stack) + np.cumsum(delta) - delta
        at_root = np.flatnonzero(before == 0)
        if len(at_root):
            if close[at_root].any() or self_[at_root].any() or len(at_root) > 1 \
                    or self.root is not None:
                raise Unsure  # a second root, or a stray close tag
            self.root = True
        paired = np.flatnonzero(~self_)
        level = np.where(close, before - 1, before)[paired]
        d = len(self.stack)
        lev = np.concatenate([np.arange(d, dtype=np.int64), level])
        cl = np.concatenate([np.zeros(d, dtype=bool), close[paired]])
        ids = np.concatenate([np.asarray(self.stack, dtype=np.uint64).reshape(d, 2),
                              ident[paired]])
        order = np.argsort(lev, kind="stable")
        lev, cl, ids = lev[order], cl[order], ids[order]
        j = np.flatnonzero(cl)
        if len(j):
            if j[0] == 0:
                raise Unsure
            p = j - 1
            if not ((lev[p] == lev[j]) & ~cl[p] & (ids[p] == ids[j]).all(axis=1)).all():
                raise Unsure  # mismatched tags
        depth = int(before[-1] + delta[-1])
        last = np.flatnonzero(np.r_[lev[1:] != lev[:-1], True])
        last = last[lev[last] < depth]
        if len(last) != depth or cl[last].any():
            raise Unsure  # pragma: no cover - implied by the pairing above
        self.stack = [tuple(x) for x in ids[last].tolist()]

        # ---------------------------------------------------------- XES
        is_attr = (code >= 1) & (code <= _NEST)
        a_delta = np.where(is_attr & ~self_, np.where(close, -1, 1), 0)
        a_before = self.attr_depth + np.cumsum(a_delta) - a_delta
        self.attr_depth = int(a_before[-1] + a_delta[-1])
        active = a_before == 0
        ev = active & (code == _EVENT)
        tr = active & (code == _TRACE)
        ev_open, ev_close = ev & ~close, ev & (close | self_)
        tr_open, tr_close = tr & ~close, tr & (close | self_)
        n_ev_before = self.n_ev + np.cumsum(ev_close) - ev_close
        n_tr_before = self.n_tr + np.cumsum(tr_close) - tr_close
        sp = np.flatnonzero(ev | tr)
        after = np.full(n, _OUT, dtype=np.int8)
        after[ev_open & ~self_] = _IN_EVENT
        after[ev_close | (tr_open & ~self_)] = _IN_TRACE
        st = after[sp]

        def state_before(pos):
            if not len(sp):
                return np.full(len(pos), self.state, dtype=np.int8)
            k = np.searchsorted(sp, pos) - 1
            return np.where(k >= 0, st[np.maximum(k, 0)], self.state)

        eo = np.flatnonzero(ev_open)
        if len(eo):
            bad = state_before(eo) != _IN_TRACE
            self.stray.extend(n_ev_before[eo[bad]].tolist())
        to = np.flatnonzero(tr_open)
        tc = np.flatnonzero(tr_close)
        if len(tc):
            m = np.searchsorted(to, tc, side="right") - 1
            start = np.where(m >= 0, n_ev_before[to[np.maximum(m, 0)]] if len(to) else 0,
                             self.tr_start)
            self.counts.append(n_ev_before[tc] - start)
        if len(to):
            self.tr_start = int(n_ev_before[to[-1]])
        at = np.flatnonzero(active & ~close & (code >= 1) & (code <= 6))
        table = state_before(at) if len(at) else at
        if len(sp):
            self.state = int(st[-1])
        self.n_ev = int(n_ev_before[-1] + ev_close[-1])
        self.n_tr = int(n_tr_before[-1] + tr_close[-1])
        for where, owners, cols in ((_IN_EVENT, n_ev_before, self.events),
                                    (_IN_TRACE, n_tr_before, self.traces)):
            sel = at[table == where]
            if len(sel):
                self._collect(a, words, sel, owners[sel], code[sel], plain, q, qs, slow_kv,
                              cols)

    def _collect(self, a, words, sel, owners, codes, plain, q, qs, slow_kv, cols):
        fast = plain[sel]
        base = qs[sel]
        f = np.flatnonzero(fast)
        if len(f) == len(sel):
            inverse, names = _keys(a, words, q[base] + 1, q[base + 1])
        else:
            keys = np.empty(len(sel), dtype=object)
            if len(f):
                k_inv, k_names = _keys(a, words, q[base[f]] + 1, q[base[f] + 1])
                keys[f] = np.array(k_names, dtype=object)[k_inv]
            for k in np.flatnonzero(~fast):
                key, value = slow_kv[int(sel[k])]
                if key is None or value is None:
                    raise Unsure  # the expat reader files it under the key None
                keys[k] = key
            inverse, uniq = pd.factorize(keys)
            names = list(uniq)
        groups, _ = _groups(inverse, len(names))
        if len(q):  # where the values of the plain tags are (the others' are not used)
            v0 = q[np.minimum(base + 2, len(q) - 1)] + 1
            v1 = q[np.minimum(base + 3, len(q) - 1)]
        else:
            v0 = v1 = np.zeros(len(sel), dtype=np.int64)
        for key, rows in zip(names, groups):  # keys in order of first appearance
            kinds = codes[rows]
            col = cols.get(key)
            if col is None:
                col = cols[key] = _Key(_TYPED[int(kinds[0]) - 1])
            if (kinds != kinds[0]).any() or _TYPED[int(kinds[0]) - 1] != col.kind:
                col.mixed = True
            col.owners.append(owners[rows])
            quick = fast[rows]
            if quick.all():
                col.values.extend(_spans(a, v0[rows], v1[rows]))
                continue
            values = np.empty(len(rows), dtype=object)
            values[quick] = _spans(a, v0[rows[quick]], v1[rows[quick]])
            values[~quick] = [slow_kv[int(sel[r])][1] for r in rows[~quick]]
            col.values.extend(values.tolist())

    # ------------------------------------------------------------------ names
    def _names(self, ident):
        if self.codes is not None:
            return
        first = ident[0]
        raw = first.tobytes().rstrip(b"\x00")
        prefix = raw[:-3] if raw.endswith(b"log") else b""
        vocab = [(prefix + t.encode(), i + 1) for i, t in enumerate(_TYPED)]
        vocab += [(prefix + t.encode(), _NEST) for t in _NESTING]
        vocab += [(prefix + b"event", _EVENT), (prefix + b"trace", _TRACE)]
        ids = _ident([v for v, _ in vocab])
        self.codes = [(int(x[0]), int(x[1]), c) for x, (_, c) in zip(ids, vocab)]

    def _check_names(self, data, ident, code, ns, nl):
        """Tags that are not XES's own: their names must be XML names (checked once each)."""
        other = np.flatnonzero(code == _OTHER)
        if not len(other):
            return
        _, first = np.unique(ident[other], axis=0, return_index=True)
        for i in other[first]:
            if not _NAME_RE.match(data, int(ns[i]), int(ns[i] + nl[i])):
                raise Unsure

    def _code(self, ident):
        code = np.zeros(len(ident), dtype=np.int8)
        for i0, i1, c in self.codes:
            code[(ident[:, 0] == i0) & (ident[:, 1] == i1)] = c
        return code

    def result(self):
        if self.root is None or self.stack:
            raise Unsure  # no element, or the document ends inside one
        counts = np.concatenate(self.counts) if self.counts else np.zeros(0, np.int64)
        out = []
        for cols in (self.events, self.traces):
            out.append({k: (np.concatenate(c.owners), c.values, c.kind, c.mixed)
                        for k, c in cols.items()})
        return out[0], out[1], counts.astype(np.int64), self.stray, self.n_ev, self.n_tr


def scan_xes(fh, chunk=CHUNK):
    """Scan an open binary XES stream: event columns, trace columns, counts, strays, sizes.

    Returns ``(events, traces, counts, stray, n_events, n_traces)`` where ``events`` and
    ``traces`` map each key to ``(owners, values, kind, mixed)``. Raises :class:`Unsure`
    for anything the expat reader should decide.
    """
    scanner = _Scanner()
    data = fh.read(chunk)
    while b">" not in data:  # the XML declaration whole, whatever the chunk size
        more = fh.read(chunk)
        if not more:
            break
        data += more
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    if data.startswith(b"<?xml"):
        m = _DECL.match(data)
        if m is None:
            raise Unsure
        enc = m.group(2)
        if enc is not None and enc[1:-1].lower() != b"utf-8":
            raise Unsure
        data = data[m.end():]
    while True:
        more = fh.read(chunk)
        if not more:
            scanner.piece(data)
            break
        data += more
        cut = data.rfind(b"<")
        if cut > 0:
            scanner.piece(data[:cut])
            data = data[cut:]
    return scanner.result()
