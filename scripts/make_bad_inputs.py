#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Generates the bad-input catalogue (tests/data/bad/) and the fuzz seed corpus from the assets.

    python3 scripts/make_bad_inputs.py [--out DIR] [--corpus DIR] [--check]

Every file is derived from a model in assets/ by a deterministic edit (standard library only),
so the catalogue can be regenerated at any time and a test checks that the committed copy
matches this script. tests/cli/bad_input_test.cpp states, per file, what `deepcut info` and
`deepcut convert` must do with it: refuse it (exit 2, one stderr line naming the file and the
problem) or handle it (exit 0, the problem listed in `info --json`, a valid export).

The seed corpus of the glTF fuzzer (tests/fuzz/corpus/gltf/) is a few small files that reach
every decoding path (glb and gltf, strips, fans, sparse, normalised integers, two influence
sets, matrices, cubic splines) plus a few catalogue files.

  --out DIR     the catalogue (default: tests/data/bad in this repository)
  --corpus DIR  the seed corpus (default: tests/fuzz/corpus/gltf in this repository)
  --check       write nothing; exit 1 when a folder differs from what the script would write
"""

import argparse
import base64
import copy
import json
import math
import os
import random
import struct
import sys
import tempfile
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ASSETS = os.path.join(ROOT, "assets")

BYTE, UBYTE, SHORT, USHORT, UINT, FLOAT = 5120, 5121, 5122, 5123, 5125, 5126
FORMATS = {BYTE: "b", UBYTE: "B", SHORT: "h", USHORT: "H", UINT: "I", FLOAT: "f"}
COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
GLB_JSON, GLB_BIN = 0x4E4F534A, 0x004E4942


class Gltf:
    """A glTF document with its buffers decoded to bytes."""

    def __init__(self, doc, buffers):
        self.doc = doc
        self.buffers = [bytearray(b) for b in buffers]

    @staticmethod
    def load_gltf(path):
        with open(path, "rb") as f:
            doc = json.loads(f.read().decode("utf-8"))
        buffers = []
        for b in doc.get("buffers", []):
            uri = b["uri"]
            if uri.startswith("data:"):
                buffers.append(base64.b64decode(uri.split(",", 1)[1]))
            else:
                with open(os.path.join(os.path.dirname(path), uri), "rb") as f:
                    buffers.append(f.read())
        return Gltf(doc, buffers)

    @staticmethod
    def load_glb(path):
        with open(path, "rb") as f:
            data = f.read()
        magic, version, length = struct.unpack_from("<4sII", data, 0)
        assert magic == b"glTF" and version == 2 and length == len(data), path
        doc, bin_chunk, offset = None, b"", 12
        while offset < length:
            size, kind = struct.unpack_from("<II", data, offset)
            chunk = data[offset + 8 : offset + 8 + size]
            if kind == GLB_JSON:
                doc = json.loads(chunk.decode("utf-8"))
            elif kind == GLB_BIN:
                bin_chunk = chunk
            offset += 8 + size
        return Gltf(doc, [bin_chunk])

    def copy(self):
        return Gltf(copy.deepcopy(self.doc), [bytes(b) for b in self.buffers])

    # ---- accessors ---------------------------------------------------------------------------
    def _layout(self, index):
        acc = self.doc["accessors"][index]
        view = self.doc["bufferViews"][acc["bufferView"]]
        comps = COMPONENTS[acc["type"]]
        fmt = "<" + FORMATS[acc["componentType"]] * comps
        stride = view.get("byteStride") or struct.calcsize(fmt)
        start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
        return view["buffer"], start, stride, acc["count"], fmt

    def read(self, index):
        """The accessor's elements as a list of tuples."""
        buf, start, stride, count, fmt = self._layout(index)
        return [struct.unpack_from(fmt, self.buffers[buf], start + i * stride) for i in range(count)]

    def write(self, index, elements):
        """Overwrites the accessor's elements in place (same count and type)."""
        buf, start, stride, count, fmt = self._layout(index)
        assert len(elements) == count
        for i, e in enumerate(elements):
            struct.pack_into(fmt, self.buffers[buf], start + i * stride, *e)

    def add_accessor(self, elements, component_type, kind, target=None):
        """Appends the elements to buffer 0 as a new bufferView and accessor; returns its index."""
        fmt = "<" + FORMATS[component_type] * COMPONENTS[kind]
        data = b"".join(struct.pack(fmt, *e) for e in elements)
        buf = self.buffers[0]
        while len(buf) % 4:
            buf.append(0)
        view = {"buffer": 0, "byteOffset": len(buf), "byteLength": len(data)}
        if target:
            view["target"] = target
        buf.extend(data)
        self.doc["bufferViews"].append(view)
        acc = {"bufferView": len(self.doc["bufferViews"]) - 1, "componentType": component_type,
               "count": len(elements), "type": kind}
        if kind == "VEC3" and component_type == FLOAT and elements:
            acc["min"] = [min(e[c] for e in elements) for c in range(3)]
            acc["max"] = [max(e[c] for e in elements) for c in range(3)]
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    # ---- output ------------------------------------------------------------------------------
    def _synced_doc(self):
        doc = copy.deepcopy(self.doc)
        for i, b in enumerate(doc.get("buffers", [])):
            if i < len(self.buffers):
                b["byteLength"] = len(self.buffers[i])
        return doc

    def gltf_bytes(self):
        """The document with every buffer embedded as a base64 data URI."""
        doc = self._synced_doc()
        for i, b in enumerate(doc.get("buffers", [])):
            b["uri"] = "data:application/octet-stream;base64," + base64.b64encode(bytes(self.buffers[i])).decode()
        return dumps(doc)

    def glb_bytes(self):
        """A .glb with all buffers merged into the BIN chunk."""
        doc = self._synced_doc()
        merged, starts = bytearray(), []
        for b in self.buffers:
            while len(merged) % 4:
                merged.append(0)
            starts.append(len(merged))
            merged.extend(b)
        for v in doc.get("bufferViews", []):
            v["byteOffset"] = v.get("byteOffset", 0) + starts[v["buffer"]]
            v["buffer"] = 0
        doc["buffers"] = [{"byteLength": len(merged)}]
        return make_glb(dumps(doc), bytes(merged))


def dumps(doc):
    return json.dumps(doc, separators=(",", ":"), allow_nan=False).encode("utf-8")


def pad(data, fill):
    return data + fill * ((4 - len(data) % 4) % 4)


def make_glb(json_bytes, bin_bytes):
    j = pad(json_bytes, b" ")
    chunks = struct.pack("<II", len(j), GLB_JSON) + j
    if bin_bytes is not None:
        b = pad(bin_bytes, b"\0")
        chunks += struct.pack("<II", len(b), GLB_BIN) + b
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def png_chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png_header(width, height):
    """A PNG signature and IHDR chunk claiming width x height RGBA pixels, and no pixel data."""
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", ihdr) + png_chunk(b"IEND", b"")


def png_2x2():
    """A complete 2 x 2 RGBA PNG."""
    ihdr = struct.pack(">IIBBBBB", 2, 2, 8, 6, 0, 0, 0)
    rows = b"".join(b"\0" + b"".join(bytes([200, 40 * y, 80 * x, 255]) for x in range(2)) for y in range(2))
    return b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", ihdr) + png_chunk(b"IDAT", zlib.compress(rows, 9)) + png_chunk(b"IEND", b"")


# ---- the catalogue ------------------------------------------------------------------------------
# Each builder returns {relative path: bytes}. SimpleSkin (10 vertices, 8 triangles, 2 joints) is
# the base for most cases: small, skinned and animated. Its accessors: 0 indices (USHORT), 1
# POSITION, 2 JOINTS_0, 3 WEIGHTS_0, 4 inverseBindMatrices, 5 key times, 6 rotations.
CASES = []


def case(name, what):
    def register(builder):
        CASES.append((name, what, builder))
        return builder

    return register


def simple_skin():
    return Gltf.load_gltf(os.path.join(ASSETS, "models", "SimpleSkin", "SimpleSkin.gltf"))


def rigged_simple():
    return Gltf.load_gltf(os.path.join(ASSETS, "models", "RiggedSimple", "RiggedSimple.gltf"))


def edit_json(edit):
    """A builder that applies `edit(doc)` to SimpleSkin's JSON and writes a .gltf."""

    def build(name):
        g = simple_skin()
        edit(g.doc)
        return {name: g.gltf_bytes()}

    return build


def with_indices(extra):
    """SimpleSkin with extra triangles (and extra vertices) appended; the skin stays valid."""

    def build(name):
        g = simple_skin()
        pos, joints, weights = g.read(1), g.read(2), g.read(3)
        idx = [i[0] for i in g.read(0)]
        new_pos, new_idx = extra(pos, idx)
        for p in new_pos:
            pos.append(p)
            joints.append((0, 1, 0, 0))
            weights.append((1.0, 0.0, 0.0, 0.0))
        prim = g.doc["meshes"][0]["primitives"][0]
        prim["attributes"]["POSITION"] = g.add_accessor(pos, FLOAT, "VEC3", 34962)
        prim["attributes"]["JOINTS_0"] = g.add_accessor(joints, USHORT, "VEC4", 34962)
        prim["attributes"]["WEIGHTS_0"] = g.add_accessor(weights, FLOAT, "VEC4", 34962)
        prim["indices"] = g.add_accessor([(i,) for i in idx + new_idx], USHORT, "SCALAR", 34963)
        return {name: g.gltf_bytes()}

    return build


def simple_glb():
    return simple_skin().glb_bytes()


# ---- containers --------------------------------------------------------------------------------
@case("control_simple_skin.glb", "SimpleSkin packed as a .glb: a good file, the control for the .glb cases")
def _(name):
    return {name: simple_glb()}


@case("glb_empty.glb", "zero bytes")
def _(name):
    return {name: b""}


@case("glb_truncated.glb", "RiggedFigure.glb cut off at 60% of its length")
def _(name):
    with open(os.path.join(ASSETS, "models", "RiggedFigure", "RiggedFigure.glb"), "rb") as f:
        data = f.read()
    return {name: data[: len(data) * 6 // 10]}


@case("glb_truncated_header.glb", "only the first 10 bytes of the 12-byte .glb header")
def _(name):
    return {name: simple_glb()[:10]}


@case("glb_wrong_magic.glb", "the magic says 'glTX' instead of 'glTF'")
def _(name):
    return {name: b"glTX" + simple_glb()[4:]}


@case("glb_version_1.glb", "the .glb header claims container version 1")
def _(name):
    data = bytearray(simple_glb())
    struct.pack_into("<I", data, 4, 1)
    return {name: bytes(data)}


@case("glb_length_past_end.glb", "the header's total length is 1 MiB, the file is far shorter")
def _(name):
    data = bytearray(simple_glb())
    struct.pack_into("<I", data, 8, 1 << 20)
    return {name: bytes(data)}


@case("glb_json_chunk_past_end.glb", "the JSON chunk length runs past the end of the file")
def _(name):
    data = bytearray(simple_glb())
    struct.pack_into("<I", data, 12, 0xFFFFFF00)
    return {name: bytes(data)}


@case("glb_bin_chunk_past_end.glb", "the BIN chunk length runs past the end of the file")
def _(name):
    data = bytearray(simple_glb())
    json_len = struct.unpack_from("<I", data, 12)[0]
    struct.pack_into("<I", data, 20 + json_len, 0x7FFFFFF0)
    return {name: bytes(data)}


@case("glb_first_chunk_not_json.glb", "the first chunk is typed BIN instead of JSON")
def _(name):
    data = bytearray(simple_glb())
    struct.pack_into("<I", data, 16, GLB_BIN)
    return {name: bytes(data)}


@case("glb_buffer_longer_than_bin.glb", "buffer 0 claims 1 MiB, the BIN chunk holds far less")
def _(name):
    g = simple_skin()
    data = g.glb_bytes()
    json_len = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20 : 20 + json_len])
    doc["buffers"][0]["byteLength"] = 1 << 20
    bin_len = struct.unpack_from("<I", data, 20 + json_len)[0]
    return {name: make_glb(dumps(doc), data[28 + json_len : 28 + json_len + bin_len])}


# ---- JSON ----------------------------------------------------------------------------------------
@case("json_syntax_error.gltf", "SimpleSkin's JSON cut off in the middle of the accessors")
def _(name):
    text = simple_skin().gltf_bytes()
    return {name: text[: text.index(b'"accessors"') + 40]}


@case("json_not_object.gltf", "valid JSON whose top level is an array")
def _(name):
    return {name: b'[{"asset": {"version": "2.0"}}]'}


@case("json_no_asset.gltf", "SimpleSkin without the required 'asset' object")
def _(name):
    return edit_json(lambda d: d.pop("asset"))(name)


@case("json_version_1.gltf", "asset.version is '1.0' (glTF 1 is not supported)")
def _(name):
    return edit_json(lambda d: d["asset"].update(version="1.0"))(name)


@case("json_deep_nesting.gltf", "100000 nested arrays in the root 'extras' (a stack-depth bomb)")
def _(name):
    text = simple_skin().gltf_bytes()
    depth = 100000
    return {name: text[:-1] + b',"extras":' + b"[" * depth + b"]" * depth + b"}"}


@case("json_random_bytes.gltf", "4 KiB of seeded random bytes")
def _(name):
    rng = random.Random(10)
    return {name: bytes(rng.randrange(256) for _ in range(4096))}


@case("not_a_model.txt", "a text file, no model: neither a known extension nor glTF inside")
def _(name):
    return {name: b"# Shopping list\n\n- bread\n- milk\n"}


@case("json_wrong_types.gltf", "'accessors' is an object and a count is a string")
def _(name):
    def edit(d):
        d["accessors"][0]["count"] = "twenty-four"
        d["accessors"] = {"0": d["accessors"][0]}

    return edit_json(edit)(name)


# ---- accessors, buffer views, buffers --------------------------------------------------------
@case("accessor_missing.gltf", "the indices name accessor 42, which does not exist")
def _(name):
    return edit_json(lambda d: d["meshes"][0]["primitives"][0].update(indices=42))(name)


@case("accessor_past_buffer_view.gltf", "the indices accessor claims 100000 elements in a 48-byte bufferView")
def _(name):
    return edit_json(lambda d: d["accessors"][0].update(count=100000))(name)


@case("accessor_offset_overflow.gltf", "POSITION's byteOffset is 2^64 - 100, so offset + size wraps around (an overflow bait)")
def _(name):
    return edit_json(lambda d: d["accessors"][1].update(byteOffset=(1 << 64) - 100))(name)


@case("accessor_stride_too_small.gltf", "the JOINTS_0/WEIGHTS_0 bufferView has a byteStride of 4 for 8- and 16-byte elements")
def _(name):
    return edit_json(lambda d: d["bufferViews"][2].update(byteStride=4))(name)


@case("accessor_bad_component_type.gltf", "POSITION has componentType 5130 (a double), which glTF does not have")
def _(name):
    return edit_json(lambda d: d["accessors"][1].update(componentType=5130))(name)


@case("accessor_sparse_index_out_of_range.gltf", "a sparse POSITION override targets element 1000 of 10")
def _(name):
    g = simple_skin()
    values = g.add_accessor([(0.0, 0.0, 1.0)], FLOAT, "VEC3")
    indices = g.add_accessor([(1000,)], UINT, "SCALAR")
    vv, iv = g.doc["accessors"][values]["bufferView"], g.doc["accessors"][indices]["bufferView"]
    g.doc["accessors"] = g.doc["accessors"][:values]
    g.doc["accessors"][1]["sparse"] = {"count": 1, "indices": {"bufferView": iv, "componentType": UINT},
                                       "values": {"bufferView": vv}}
    return {name: g.gltf_bytes()}


@case("buffer_view_missing.gltf", "POSITION names bufferView 99, which does not exist")
def _(name):
    return edit_json(lambda d: d["accessors"][1].update(bufferView=99))(name)


@case("buffer_view_past_buffer.gltf", "a bufferView of 100000 bytes in a 168-byte buffer")
def _(name):
    return edit_json(lambda d: d["bufferViews"][1].update(byteLength=100000))(name)


@case("buffer_missing.gltf", "a bufferView names buffer 9, which does not exist")
def _(name):
    return edit_json(lambda d: d["bufferViews"][1].update(buffer=9))(name)


@case("buffer_bad_base64.gltf", "buffer 0 is a data URI that is not base64")
def _(name):
    g = simple_skin()
    text = g.gltf_bytes()
    doc = json.loads(text)
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64,!!!not*base64!!!"
    return {name: dumps(doc)}


@case("buffer_length_mismatch.gltf", "buffer 0 claims 1 GB, its data URI holds 168 bytes")
def _(name):
    g = simple_skin()
    doc = json.loads(g.gltf_bytes())
    doc["buffers"][0]["byteLength"] = 1000000000
    return {name: dumps(doc)}


@case("index_past_vertex_count.gltf", "index 5 of SimpleSkin's 24 is 65000; there are 10 vertices")
def _(name):
    g = simple_skin()
    idx = g.read(0)
    idx[5] = (65000,)
    g.write(0, idx)
    return {name: g.gltf_bytes()}


@case("index_count_not_multiple_of_3.gltf", "23 indices for a TRIANGLES primitive")
def _(name):
    return edit_json(lambda d: d["accessors"][0].update(count=23))(name)


@case("triangles_10m_claim.gltf", "the indices accessor claims 30 million elements (10M triangles) in a 48-byte bufferView")
def _(name):
    return edit_json(lambda d: d["accessors"][0].update(count=30000000))(name)


@case("triangles_10m_sparse_claim.gltf",
      "a non-indexed primitive whose POSITION accessor has no bufferView and claims 30 million zero vertices "
      "(10M triangles), with one sparse override")
def _(name):
    g = simple_skin()
    values = g.add_accessor([(0.0, 0.0, 1.0)], FLOAT, "VEC3")
    indices = g.add_accessor([(0,)], UINT, "SCALAR")
    vv, iv = g.doc["accessors"][values]["bufferView"], g.doc["accessors"][indices]["bufferView"]
    g.doc["accessors"][values] = {"componentType": FLOAT, "count": 30000000, "type": "VEC3",
                                  "sparse": {"count": 1, "indices": {"bufferView": iv, "componentType": UINT},
                                             "values": {"bufferView": vv}}}
    g.doc["accessors"].pop()
    g.doc["meshes"][0]["primitives"][0] = {"attributes": {"POSITION": values}}
    return {name: g.gltf_bytes()}


@case("accessor_reused_amplification.gltf",
      "600 primitives share one zero-filled POSITION accessor of 999999 vertices: 7 GB to decode from 20 KB "
      "(an amplification bomb)")
def _(name):
    g = simple_skin()
    g.doc["accessors"].append({"componentType": FLOAT, "count": 999999, "type": "VEC3"})
    prim = {"attributes": {"POSITION": len(g.doc["accessors"]) - 1}}
    g.doc["meshes"][0]["primitives"] = [prim] * 600
    return {name: g.gltf_bytes()}


@case("primitive_lines.gltf", "the primitive is LINES (mode 1)")
def _(name):
    return edit_json(lambda d: d["meshes"][0]["primitives"][0].update(mode=1))(name)


@case("primitive_no_position.gltf", "the primitive has no POSITION attribute")
def _(name):
    return edit_json(lambda d: d["meshes"][0]["primitives"][0]["attributes"].pop("POSITION"))(name)


@case("attribute_bad_texcoord_name.gltf", "an attribute named TEXCOORD_x (not a number), sharing POSITION's data")
def _(name):
    return edit_json(lambda d: d["meshes"][0]["primitives"][0]["attributes"].update(TEXCOORD_x=1))(name)


# ---- geometry ------------------------------------------------------------------------------------
@case("position_nan.gltf", "POSITION 3 is (NaN, 0.5, 0)")
def _(name):
    g = simple_skin()
    pos = g.read(1)
    pos[3] = (float("nan"), pos[3][1], pos[3][2])
    g.write(1, pos)
    return {name: g.gltf_bytes()}


@case("position_inf.gltf", "POSITION 7 is (1, +Inf, 0)")
def _(name):
    g = simple_skin()
    pos = g.read(1)
    pos[7] = (pos[7][0], float("inf"), pos[7][2])
    g.write(1, pos)
    return {name: g.gltf_bytes()}


@case("zero_vertex_mesh.gltf", "a mesh whose POSITION accessor has 0 elements and no indices")
def _(name):
    def edit(d):
        d["accessors"].append({"bufferView": 1, "componentType": FLOAT, "count": 0, "type": "VEC3"})
        d["meshes"].append({"name": "empty", "primitives": [{"attributes": {"POSITION": len(d["accessors"]) - 1}}]})
        d["nodes"].append({"name": "empty", "mesh": len(d["meshes"]) - 1})
        d["scenes"][0]["nodes"].append(len(d["nodes"]) - 1)

    return edit_json(edit)(name)


@case("triangles_zero_area.gltf", "two extra triangles: one collinear (0, 2, 4), one with a repeated vertex (1, 1, 3)")
def _(name):
    return with_indices(lambda pos, idx: ([], [0, 2, 4, 1, 1, 3]))(name)


@case("triangles_duplicate.gltf", "the first two triangles appear twice, once with the same winding, once reversed")
def _(name):
    return with_indices(lambda pos, idx: ([], idx[0:3] + [idx[5], idx[4], idx[3]]))(name)


@case("nonmanifold_vertex.gltf", "a second triangle touches the strip only at corner vertex 9 (a bow tie)")
def _(name):
    return with_indices(lambda pos, idx: ([(2.0, 2.0, 0.0), (2.0, 3.0, 0.0)], [9, len(pos), len(pos) + 1]))(name)


@case("edge_with_three_faces.gltf", "a fin: a third triangle on the interior edge (2, 3)")
def _(name):
    return with_indices(lambda pos, idx: ([(0.5, 0.5, 1.0)], [2, 3, len(pos)]))(name)


@case("normals_inverted.gltf", "RiggedSimple with every NORMAL negated (pointing into the closed cylinder)")
def _(name):
    g = rigged_simple()
    acc = g.doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"]
    g.write(acc, [(-x, -y, -z) for (x, y, z) in g.read(acc)])
    lo, hi = g.doc["accessors"][acc]["min"], g.doc["accessors"][acc]["max"]
    g.doc["accessors"][acc]["min"], g.doc["accessors"][acc]["max"] = [-v for v in hi], [-v for v in lo]
    return {name: g.gltf_bytes()}


# ---- skins -----------------------------------------------------------------------------------
@case("weights_sum_zero.gltf", "vertices 0-3 have all four weights 0")
def _(name):
    g = simple_skin()
    w = g.read(3)
    for v in range(4):
        w[v] = (0.0, 0.0, 0.0, 0.0)
    g.write(3, w)
    return {name: g.gltf_bytes()}


@case("weights_sum_seven.gltf", "every vertex's weights sum to 7")
def _(name):
    g = simple_skin()
    g.write(3, [(7.0 * a, 7.0 * b, 7.0 * c, 7.0 * d) for (a, b, c, d) in g.read(3)])
    return {name: g.gltf_bytes()}


@case("weights_negative_nan.gltf", "vertex 4 has weights (NaN, 1, 0, 0), vertex 5 has (-1, 2, 0, 0)")
def _(name):
    g = simple_skin()
    w = g.read(3)
    w[4] = (float("nan"), 1.0, 0.0, 0.0)
    w[5] = (-1.0, 2.0, 0.0, 0.0)
    g.write(3, w)
    return {name: g.gltf_bytes()}


@case("joint_past_skin.gltf", "vertices 6-9 name joint 7 with weight 0.5; the skin has 2 joints")
def _(name):
    g = simple_skin()
    j, w = g.read(2), g.read(3)
    for v in range(6, 10):
        j[v] = (0, 7, 0, 0)
        w[v] = (0.5, 0.5, 0.0, 0.0)
    g.write(2, j)
    g.write(3, w)
    return {name: g.gltf_bytes()}


@case("weights_sum_098.gltf", "every vertex's weights sum to 0.98 (inside the old 1e-3 slack, outside the validator's)")
def _(name):
    g = simple_skin()
    g.write(3, [(0.98 * a, 0.98 * b, 0.98 * c, 0.98 * d) for (a, b, c, d) in g.read(3)])
    return {name: g.gltf_bytes()}


@case("skin_ibm_last_row_noise.gltf", "both inverse bind matrices end in 1.0000001 and one has 1e-8 in its last row")
def _(name):
    g = simple_skin()
    m = [list(x) for x in g.read(4)]
    for x in m:
        x[15] = 1.0000001
    m[1][3] = 1e-8
    g.write(4, [tuple(x) for x in m])
    return {name: g.gltf_bytes()}


@case("skin_ibm_not_affine.gltf", "inverse bind matrix 1 has 0.5 in its last row (projective, not an inverse bind matrix)")
def _(name):
    g = simple_skin()
    m = [list(x) for x in g.read(4)]
    m[1][7] = 0.5
    g.write(4, [tuple(x) for x in m])
    return {name: g.gltf_bytes()}


@case("skin_joint_listed_twice.gltf", "the skin lists node 1 twice (joints 0 and 2, same inverse bind matrix); vertices 0-4 use joint 2")
def _(name):
    g = simple_skin()
    m = g.read(4)
    g.doc["skins"][0]["joints"].append(g.doc["skins"][0]["joints"][0])
    g.doc["skins"][0]["inverseBindMatrices"] = g.add_accessor([m[0], m[1], m[0]], FLOAT, "MAT4")
    j = g.read(2)
    for v in range(5):
        j[v] = tuple(2 if x == 0 else x for x in j[v])
    g.write(2, j)
    return {name: g.gltf_bytes()}


@case("skin_joint_listed_twice_other_ibm.gltf",
      "the skin lists node 1 twice, the second time with its inverse bind matrix moved by 0.5 in y; vertices 0-4 use it")
def _(name):
    g = simple_skin()
    m = g.read(4)
    moved = m[0][:13] + (m[0][13] + 0.5,) + m[0][14:]
    g.doc["skins"][0]["joints"].append(g.doc["skins"][0]["joints"][0])
    g.doc["skins"][0]["inverseBindMatrices"] = g.add_accessor([m[0], m[1], moved], FLOAT, "MAT4")
    j = g.read(2)
    for v in range(5):
        j[v] = tuple(2 if x == 0 else x for x in j[v])
    g.write(2, j)
    return {name: g.gltf_bytes()}


@case("joints_repeated_in_vertex.gltf", "vertices 2 and 3 name joint 1 in two slots, each with weight 0.25, plus joint 0 with 0.5")
def _(name):
    g = simple_skin()
    j, w = g.read(2), g.read(3)
    for v in (2, 3):
        j[v] = (0, 1, 1, 0)
        w[v] = (0.5, 0.25, 0.25, 0.0)
    g.write(2, j)
    g.write(3, w)
    return {name: g.gltf_bytes()}


@case("extras_and_extensions.gltf",
      "asset.extras (CC-BY attribution), copyright, node, mesh and material extras, a root extension (kept), "
      "an unknown mesh extension and skin extras (both dropped, so named)")
def _(name):
    def edit(d):
        d["asset"]["copyright"] = "2024 A. Modeller"
        d["asset"]["extras"] = {"title": "Skin", "author": "A. Modeller", "license": "CC-BY-4.0",
                                "source": "https://example.org/skin"}
        d["nodes"][0]["extras"] = {"role": "body"}
        d["meshes"][0]["extras"] = {"lod": 0}
        d["materials"] = [{"name": "skin", "extras": {"shader": "toon"}}]
        d["meshes"][0]["primitives"][0]["material"] = 0
        d["extensionsUsed"] = ["EXT_deepcut_root_test", "EXT_deepcut_mesh_test"]
        d["extensions"] = {"EXT_deepcut_root_test": {"note": "kept"}}
        d["meshes"][0]["extensions"] = {"EXT_deepcut_mesh_test": {"note": "dropped"}}
        d["skins"][0]["extras"] = {"rig": "v2"}

    return edit_json(edit)(name)


@case("skin_without_inverse_bind_matrices.gltf", "the skin omits inverseBindMatrices (identity by the spec)")
def _(name):
    return edit_json(lambda d: d["skins"][0].pop("inverseBindMatrices"))(name)


@case("skin_too_few_inverse_bind_matrices.gltf", "2 joints, 1 inverse bind matrix")
def _(name):
    return edit_json(lambda d: d["accessors"][4].update(count=1))(name)


@case("skin_inverse_bind_matrix_nan.gltf", "inverse bind matrix 1 holds a NaN")
def _(name):
    g = simple_skin()
    m = g.read(4)
    m[1] = m[1][:12] + (float("nan"),) + m[1][13:]
    g.write(4, m)
    return {name: g.gltf_bytes()}


@case("skin_joint_missing_node.gltf", "the skin names joint node 40, which does not exist")
def _(name):
    return edit_json(lambda d: d["skins"][0]["joints"].append(40))(name)


@case("node_cycle.gltf", "node 2 lists node 0 as its child (a cycle)")
def _(name):
    return edit_json(lambda d: d["nodes"][2].update(children=[0]))(name)


@case("animation_times_decreasing.gltf", "the animation's key times run backwards")
def _(name):
    g = simple_skin()
    t = g.read(5)
    g.write(5, list(reversed(t)))
    return {name: g.gltf_bytes()}


@case("animation_quaternion_not_unit.gltf", "the rotation keys are scaled by 3 (not unit quaternions) and key 0 is all zeros")
def _(name):
    g = simple_skin()
    r = [(3 * x, 3 * y, 3 * z, 3 * w) for (x, y, z, w) in g.read(6)]
    r[0] = (0.0, 0.0, 0.0, 0.0)
    g.write(6, r)
    return {name: g.gltf_bytes()}


# ---- images --------------------------------------------------------------------------------------
def with_image(image):
    def build(name):
        g = simple_skin()
        g.doc["images"] = [image(g)]
        g.doc["textures"] = [{"source": 0}]
        g.doc["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
        prim = g.doc["meshes"][0]["primitives"][0]
        prim["material"] = 0
        prim["attributes"]["TEXCOORD_0"] = g.add_accessor([(x, y / 2) for (x, y, z) in g.read(1)], FLOAT, "VEC2", 34962)
        return {name: g.gltf_bytes()}

    return build


@case("control_textured.gltf", "SimpleSkin with UVs and an embedded 2 x 2 PNG texture: a good file, the control for the image cases")
def _(name):
    return with_image(lambda g: {"uri": "data:image/png;base64," + base64.b64encode(png_2x2()).decode(), "mimeType": "image/png"})(name)


@case("image_huge_claim.gltf", "an embedded PNG whose header claims 1000000 x 1000000 pixels (no pixel data)")
def _(name):
    def image(g):
        data = png_header(1000000, 1000000)
        return {"uri": "data:image/png;base64," + base64.b64encode(data).decode(), "mimeType": "image/png"}

    return with_image(image)(name)


@case("image_view_past_buffer.gltf", "an image in a bufferView of 2 GB inside a 168-byte buffer")
def _(name):
    def image(g):
        g.doc["bufferViews"].append({"buffer": 0, "byteOffset": 0, "byteLength": 2000000000})
        return {"bufferView": len(g.doc["bufferViews"]) - 1, "mimeType": "image/png"}

    return with_image(image)(name)


@case("image_uri_escapes.gltf", "an image URI '../../../../../../etc/passwd'")
def _(name):
    return with_image(lambda g: {"uri": "../../../../../../etc/passwd"})(name)


# ---- URIs ----------------------------------------------------------------------------------------
def with_buffer_uri(uri):
    def build(name):
        g = simple_skin()
        doc = json.loads(g.gltf_bytes())
        doc["buffers"][0]["uri"] = uri
        return {name: dumps(doc)}

    return build


@case("uri_escapes_etc_passwd.gltf", "buffer 0 URI '../../etc/passwd'")
def _(name):
    return with_buffer_uri("../../etc/passwd")(name)


@case("uri_absolute.gltf", "buffer 0 URI '/etc/passwd' (absolute)")
def _(name):
    return with_buffer_uri("/etc/passwd")(name)


@case("uri_percent_encoded.gltf", "buffer 0 URI '..%2F..%2Fetc%2Fpasswd' (percent-encoded escape)")
def _(name):
    return with_buffer_uri("..%2F..%2Fetc%2Fpasswd")(name)


@case("uri_missing_file.gltf", "buffer 0 URI 'missing.bin', which is not there")
def _(name):
    return with_buffer_uri("missing.bin")(name)


@case("escape/uri_to_parent_folder.gltf",
      "buffer 0 URI '../escape_target.bin': a VALID buffer, but outside the model's folder, so a load that "
      "succeeds would prove it was read")
def _(name):
    g = simple_skin()
    doc = json.loads(g.gltf_bytes())
    doc["buffers"][0]["uri"] = "../escape_target.bin"
    return {name: dumps(doc), "escape_target.bin": bytes(g.buffers[0])}


# ---- compressed (KHR_draco_mesh_compression, EXT_meshopt_compression) ----------------------------
# Derived from assets/models/compressed/. The Draco cases keep only what CesiumMan's mesh needs
# (no image, texture, material or animation), so each file is small.
def compressed_glb(file):
    g = Gltf.load_glb(os.path.join(ASSETS, "models", "compressed", file))
    return g.doc, bytes(g.buffers[0])


def draco_cesium_man():
    """CesiumMan-draco.glb without images, materials and animations, its buffer repacked."""
    doc, data = compressed_glb("CesiumMan-draco.glb")
    for key in ("animations", "images", "textures", "samplers", "materials"):
        doc.pop(key, None)
    prim = doc["meshes"][0]["primitives"][0]
    prim.pop("material", None)
    refs = [a for a in doc["accessors"] if "bufferView" in a] + [prim["extensions"]["KHR_draco_mesh_compression"]]
    views, packed, renumber = [], bytearray(), {}
    for r in refs:
        old = r["bufferView"]
        if old not in renumber:
            v = doc["bufferViews"][old]
            renumber[old] = len(views)
            packed += b"\0" * ((4 - len(packed) % 4) % 4)
            views.append({"buffer": 0, "byteOffset": len(packed), "byteLength": v["byteLength"]})
            packed += data[v.get("byteOffset", 0) : v.get("byteOffset", 0) + v["byteLength"]]
        r["bufferView"] = renumber[old]
    doc["bufferViews"] = views
    doc["buffers"] = [{"byteLength": len(packed)}]
    return doc, bytes(packed)


def draco_case(edit):
    def build(name):
        doc, data = draco_cesium_man()
        edit(doc, doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"])
        return {name: make_glb(dumps(doc), data)}

    return build


def meshopt_case(edit):
    """Fox-meshopt.glb with `edit(doc, views)` applied; its bufferView 1 is JOINTS_0 (ATTRIBUTES,
    stride 4, 1728), 3 the QUATERNION rotations (stride 8), 4 the EXPONENTIAL translations."""

    def build(name):
        doc, data = compressed_glb("Fox-meshopt.glb")
        edit(doc, [v.get("extensions", {}).get("EXT_meshopt_compression") for v in doc["bufferViews"]])
        return {name: make_glb(dumps(doc), data)}

    return build


def _cut_draco(doc, ext):
    doc["bufferViews"][ext["bufferView"]]["byteLength"] = 1000


def _draco_points_to_animation(doc, ext):
    ext["bufferView"] = doc["accessors"][6]["bufferView"]


def _draco_count(doc, ext):
    doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]["count"] = 3000


def _draco_missing_id(doc, ext):
    ext["attributes"]["POSITION"] = 9


case("draco_truncated.glb", "CesiumMan-draco with its Draco bufferView cut to its first 1000 bytes")(
    draco_case(_cut_draco))
case("draco_not_draco.glb", "the Draco extension points at animation key times, which are not Draco data")(
    draco_case(_draco_points_to_animation))
case("draco_count_mismatch.glb", "POSITION claims 3000 vertices; the Draco data decodes 3572")(draco_case(_draco_count))
case("draco_attribute_id_missing.glb", "the extension maps POSITION to Draco attribute 9, which the data does not have")(
    draco_case(_draco_missing_id))


def _meshopt_count_overflow(doc, views):
    views[1]["count"] = 4294967295


def _meshopt_bad_filter(doc, views):
    views[4]["filter"] = "OCTAHEDRAL"


def _meshopt_unknown_filter(doc, views):
    views[4]["filter"] = "ZIGZAG"


def _meshopt_stride(doc, views):
    views[1]["byteStride"] = 8


def _meshopt_truncated(doc, views):
    views[6]["byteLength"] = 100


def _meshopt_past_buffer(doc, views):
    views[6]["byteOffset"] = 1 << 30


def _meshopt_bad_mode(doc, views):
    views[1]["mode"] = "LINES"


case("meshopt_count_overflow.glb", "a meshopt view claims 2^32 - 1 elements (count x byteStride overflows 32 bits)")(
    meshopt_case(_meshopt_count_overflow))
case("meshopt_bad_filter.glb", "filter OCTAHEDRAL on a 12-byte stride (it needs 4 or 8)")(meshopt_case(_meshopt_bad_filter))
case("meshopt_unknown_filter.glb", "filter 'ZIGZAG', which the extension does not define")(
    meshopt_case(_meshopt_unknown_filter))
case("meshopt_stride_mismatch.glb", "byteStride 8 in the extension of a bufferView of 1728 4-byte elements")(
    meshopt_case(_meshopt_stride))
case("meshopt_truncated.glb", "the compressed data of a meshopt view cut to 100 bytes")(meshopt_case(_meshopt_truncated))
case("meshopt_past_buffer.glb", "a meshopt view's compressed bytes start 1 GiB into a 57 KiB buffer")(
    meshopt_case(_meshopt_past_buffer))
case("meshopt_bad_mode.glb", "a meshopt view with mode 'LINES'")(meshopt_case(_meshopt_bad_mode))


# ---- fuzz seeds ----------------------------------------------------------------------------------
SEEDS = []  # (name, builder)
# ---- static meshes (OBJ, PLY, STL, OFF: plugins/static_formats) ----------------------------------
# Derived from assets/models/spot/spot.obj or from a unit cube written here; under static/.
CUBE_CORNERS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
CUBE_QUADS = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (1, 2, 6, 5), (0, 4, 7, 3)]


def spot_obj():
    with open(os.path.join(ASSETS, "models", "spot", "spot.obj"), "rb") as f:
        return f.read()


def cube_off(corners=CUBE_CORNERS, quads=CUBE_QUADS, counts=None):
    nv, nf = counts if counts else (len(corners), len(quads))
    lines = ["OFF", "%d %d 0" % (nv, nf)] + ["%s %s %s" % c for c in corners]
    lines += ["%d %s" % (len(q), " ".join(str(i) for i in q)) for q in quads]
    return ("\n".join(lines) + "\n").encode("ascii")


def cube_obj(corners=CUBE_CORNERS, quads=CUBE_QUADS):
    lines = ["v %s %s %s" % c for c in corners]
    lines += ["f " + " ".join(str(i + 1) for i in q) for q in quads]
    return ("\n".join(lines) + "\n").encode("ascii")


def cube_ply_binary(quads=CUBE_QUADS, vertex_count=None):
    head = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
            "property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n"
            % (vertex_count if vertex_count is not None else len(CUBE_CORNERS), len(quads)))
    body = b"".join(struct.pack("<3f", *c) for c in CUBE_CORNERS)
    body += b"".join(struct.pack("<B4i", 4, *q) for q in quads)
    return head.encode("ascii") + body


def cube_triangles():
    c = CUBE_CORNERS
    return [tri for q in CUBE_QUADS for tri in ((c[q[0]], c[q[1]], c[q[2]]), (c[q[0]], c[q[2]], c[q[3]]))]


def cube_stl_binary(count=None, edit=None):
    tris = [list(t) for t in cube_triangles()]
    if edit:
        edit(tris)
    out = b"deepcut bad-input catalogue".ljust(80, b" ") + struct.pack("<I", len(tris) if count is None else count)
    for t in tris:
        out += struct.pack("<3f", 0.0, 0.0, 0.0) + b"".join(struct.pack("<3f", *p) for p in t) + b"\0\0"
    return out


def cube_stl_ascii():
    lines = ["solid cube"]
    for t in cube_triangles():
        lines += [" facet normal 0 0 0", "  outer loop"] + ["   vertex %s %s %s" % p for p in t] + ["  endloop", " endfacet"]
    return ("\n".join(lines + ["endsolid cube"]) + "\n").encode("ascii")


@case("static/control_cube.off", "a good OFF cube of quads, the control for the static cases (quads split into fans)")
def _(name):
    return {name: cube_off()}


@case("static/control_cube_ascii.stl", "a good ASCII STL cube (12 triangles, 36 unwelded corners)")
def _(name):
    return {name: cube_stl_ascii()}


@case("static/obj_empty.obj", "zero bytes")
def _(name):
    return {name: b""}


@case("static/obj_truncated.obj", "spot.obj cut off at 20% of its length: part of the vertices, no faces")
def _(name):
    data = spot_obj()
    return {name: data[: len(data) // 5]}


@case("static/obj_index_out_of_range.obj", "a cube whose last face names vertex 99 of 8")
def _(name):
    return {name: cube_obj(quads=CUBE_QUADS[:-1] + [(0, 4, 7, 98)])}


@case("static/obj_nan.obj", "a cube with vertex 2 at (nan, 0, 0)")
def _(name):
    return {name: cube_obj(corners=CUBE_CORNERS[:1] + [("nan", 0, 0)] + CUBE_CORNERS[2:])}


@case("static/obj_binary_garbage.obj", "4 KiB of seeded random bytes")
def _(name):
    rng = random.Random(1117)
    return {name: bytes(rng.randrange(256) for _ in range(4096))}


@case("static/obj_unreferenced_vertices.obj", "a cube plus 3 vertices no face uses (handled: dropped and reported)")
def _(name):
    return {name: cube_obj(corners=CUBE_CORNERS + [(5, 5, 5), (6, 5, 5), (5, 6, 5)])}


@case("static/obj_uv_index_out_of_range.obj",
      "60 faces of spot.obj with one texture coordinate index 5454 of 71 (found by fuzz_read_obj: vtkOBJReader crashed)")
def _(name):
    with open(os.path.join(ROOT, "tests", "fuzz", "corpus", "obj", "spot_patch.obj"), "rb") as f:
        data = f.read()
    return {name: data.replace(b"f 53/53 45/45 54/54", b"f 53/53 45/5 4/5454")}


@case("static/off_truncated.off", "an OFF cube whose last two faces are missing")
def _(name):
    data = cube_off().decode("ascii").splitlines()
    return {name: ("\n".join(data[:-2]) + "\n").encode("ascii")}


@case("static/off_huge_counts.off", "an OFF header claiming 100 million vertices and 200 million faces in 40 bytes")
def _(name):
    return {name: b"OFF\n100000000 200000000 0\n0 0 0\n1 0 0\n"}


@case("static/off_index_out_of_range.off", "an OFF cube whose last face names vertex 8 of 8")
def _(name):
    return {name: cube_off(quads=CUBE_QUADS[:-1] + [(0, 4, 7, 8)])}


@case("static/off_negative_index.off", "an OFF cube whose last face names vertex -1")
def _(name):
    return {name: cube_off(quads=CUBE_QUADS[:-1] + [(0, 4, 7, -1)])}


@case("static/off_nan.off", "an OFF cube with vertex 1 at (0, inf, 0)")
def _(name):
    return {name: cube_off(corners=CUBE_CORNERS[:1] + [(0, "inf", 0)] + CUBE_CORNERS[2:])}


@case("static/off_no_faces.off", "an OFF file with 8 vertices and 0 faces")
def _(name):
    return {name: cube_off(quads=[])}


@case("static/ply_truncated.ply", "a binary PLY cube cut off in its face list")
def _(name):
    data = cube_ply_binary()
    return {name: data[:-30]}


@case("static/ply_huge_count.ply", "a binary PLY header claiming 100 million vertices, with 8 in the file")
def _(name):
    return {name: cube_ply_binary(vertex_count=100000000)}


@case("static/ply_index_out_of_range.ply", "a binary PLY cube whose last face names vertex 1000")
def _(name):
    return {name: cube_ply_binary(quads=CUBE_QUADS[:-1] + [(0, 4, 7, 1000)])}


@case("static/ply_index_huge.ply",
      "a binary PLY cube whose third face names vertex 65536 (found by fuzz_read_ply: vtkPLYReader crashed)")
def _(name):
    quads = list(CUBE_QUADS)
    quads[2] = (0, 65536, 5, 4)
    return {name: cube_ply_binary(quads=quads)}


@case("static/ply_no_end_header.ply", "a PLY header that never ends")
def _(name):
    return {name: b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n" + b"comment x\n" * 8000}


@case("static/stl_empty.stl", "zero bytes")
def _(name):
    return {name: b""}


@case("static/stl_truncated.stl", "a binary STL cube cut off in its fifth triangle")
def _(name):
    return {name: cube_stl_binary()[: 84 + 50 * 4 + 20]}


@case("static/stl_huge_count.stl", "a binary STL header claiming 10 million triangles, with 12 in the file")
def _(name):
    return {name: cube_stl_binary(count=10000000)}


@case("static/stl_solid_with_control_bytes.stl",
      "starts like an ASCII STL ('solid') but holds control bytes, so VTK reads it as binary with a huge count (found by fuzz_read_stl: 9.7 GB asked for)")
def _(name):
    return {name: cube_stl_ascii()[:100] + b"\x1e" * 312}


@case("static/stl_nan.stl", "a binary STL cube with a NaN corner in triangle 3")
def _(name):
    def edit(tris):
        tris[3][1] = (float("nan"), 0.0, 0.0)

    return {name: cube_stl_binary(edit=edit)}


SEED_FROM_CATALOGUE = ["control_simple_skin.glb", "control_textured.gltf", "skin_without_inverse_bind_matrices.gltf",
                       "triangles_duplicate.gltf", "nonmanifold_vertex.gltf", "weights_sum_zero.gltf"]


def seed(name):
    def register(builder):
        SEEDS.append((name, builder))
        return builder

    return register


@seed("strip.gltf")
def _():
    g = simple_skin()
    prim = g.doc["meshes"][0]["primitives"][0]
    prim.pop("indices")
    prim["mode"] = 5
    return g.gltf_bytes()


@seed("fan.glb")
def _():
    g = simple_skin()
    prim = g.doc["meshes"][0]["primitives"][0]
    prim["mode"] = 6
    prim["indices"] = g.add_accessor([(i,) for i in [0, 1, 3, 5, 7, 9, 8, 6, 4, 2]], UBYTE, "SCALAR", 34963)
    return g.glb_bytes()


@seed("sparse.gltf")
def _():
    g = simple_skin()
    values = g.add_accessor([(0.0, 0.5, 0.25), (1.0, 1.5, 0.25)], FLOAT, "VEC3")
    indices = g.add_accessor([(3,), (7,)], USHORT, "SCALAR")
    vv, iv = g.doc["accessors"][values]["bufferView"], g.doc["accessors"][indices]["bufferView"]
    g.doc["accessors"] = g.doc["accessors"][:values]
    g.doc["accessors"][1]["sparse"] = {"count": 2, "indices": {"bufferView": iv, "componentType": USHORT},
                                       "values": {"bufferView": vv}}
    return g.gltf_bytes()


@seed("normalized.gltf")
def _():
    g = simple_skin()
    pos = g.read(1)
    prim = g.doc["meshes"][0]["primitives"][0]
    prim["attributes"]["TEXCOORD_0"] = g.add_accessor([(int(x * 255), int(y * 127)) for (x, y, z) in pos], UBYTE, "VEC2")
    g.doc["accessors"][-1]["normalized"] = True
    prim["attributes"]["COLOR_0"] = g.add_accessor([(65535, int(y * 30000), 0) for (x, y, z) in pos], USHORT, "VEC3")
    g.doc["accessors"][-1]["normalized"] = True
    prim["attributes"]["NORMAL"] = g.add_accessor([(0, 0, 127)] * len(pos), BYTE, "VEC3")
    g.doc["accessors"][-1]["normalized"] = True
    return g.gltf_bytes()


@seed("two_influence_sets.glb")
def _():
    g = simple_skin()
    n = len(g.read(1))
    prim = g.doc["meshes"][0]["primitives"][0]
    prim["attributes"]["JOINTS_1"] = g.add_accessor([(1, 0, 0, 0)] * n, UBYTE, "VEC4")
    prim["attributes"]["WEIGHTS_1"] = g.add_accessor([(0.25, 0.0, 0.0, 0.0)] * n, FLOAT, "VEC4")
    return g.glb_bytes()


@seed("matrix_cubic.gltf")
def _():
    g = simple_skin()
    g.doc["nodes"][1].pop("translation")
    g.doc["nodes"][1]["matrix"] = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 1]
    times = [(0.0,), (1.0,), (2.0,)]
    out = []
    for k in range(3):
        half = 0.35 * k
        out += [(0.0, 0.0, 0.0, 0.0), (0.0, 0.0, math.sin(half), math.cos(half)), (0.0, 0.0, 0.0, 0.0)]
    sampler = g.doc["animations"][0]["samplers"][0]
    sampler["input"] = g.add_accessor(times, FLOAT, "SCALAR")
    sampler["output"] = g.add_accessor(out, FLOAT, "VEC4")
    sampler["interpolation"] = "CUBICSPLINE"
    return g.gltf_bytes()


# ---- driver ----------------------------------------------------------------------------------------
def generate_corpus(catalogue):
    files = {name: builder() for name, builder in SEEDS}
    for name in SEED_FROM_CATALOGUE:
        files[name] = catalogue[name]
    return files


def generate():
    files = {}
    lines = [
        "<!-- SPDX-License-Identifier: MIT -->",
        "# Bad-input catalogue",
        "",
        "Generated by `python3 scripts/make_bad_inputs.py` from the models in `assets/`; do not edit by",
        "hand. `tests/cli/bad_input_test.cpp` states what `deepcut info` and `deepcut convert` must do",
        "with each file, and checks that this folder matches the script.",
        "",
        "| file | what is wrong |",
        "| --- | --- |",
    ]
    for name, what, builder in CASES:
        out = builder(name)
        assert name in out, name
        for path, data in out.items():
            assert path not in files, path
            files[path] = data
        lines.append("| `%s` | %s |" % (name, what))
    lines.append("")
    files["README.md"] = "\n".join(lines).encode("utf-8")
    return files


def existing(folder):
    found = {}
    for dirpath, _, names in os.walk(folder):
        for n in names:
            path = os.path.join(dirpath, n)
            with open(path, "rb") as f:
                found[os.path.relpath(path, folder)] = f.read()
    return found


def check(folder, files):
    have = existing(folder) if os.path.isdir(folder) else {}
    stale = sorted(set(have) ^ set(files)) + sorted(p for p in files if p in have and have[p] != files[p])
    for p in stale:
        print("make_bad_inputs: %s differs from the generator" % os.path.join(folder, p), file=sys.stderr)
    return not stale


def write(folder, files):
    for path in existing(folder) if os.path.isdir(folder) else {}:
        if path not in files:
            os.remove(os.path.join(folder, path))
    for path, data in files.items():
        full = os.path.join(folder, path)
        os.makedirs(os.path.dirname(full), exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=os.path.dirname(full), delete=False) as tmp:
            tmp.write(data)
        os.chmod(tmp.name, 0o644)
        os.replace(tmp.name, full)
    print("make_bad_inputs: wrote %d files to %s" % (len(files), folder), file=sys.stderr)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join(ROOT, "tests", "data", "bad"))
    parser.add_argument("--corpus", default=os.path.join(ROOT, "tests", "fuzz", "corpus", "gltf"))
    parser.add_argument("--check", action="store_true")
    args = parser.parse_args()
    files = generate()
    corpus = generate_corpus(files)
    if args.check:
        ok = check(args.out, files)
        ok = check(args.corpus, corpus) and ok
        return 0 if ok else 1
    write(args.out, files)
    write(args.corpus, corpus)
    return 0


if __name__ == "__main__":
    sys.exit(main())
