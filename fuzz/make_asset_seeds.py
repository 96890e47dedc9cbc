#!/usr/bin/env python3
"""Writes the seed corpus of the `assets_archive` fuzz target (fuzz/corpus/assets_archive/):
archives holding the files the target's MJCF and URDF models reference (a.stl,
meshes/b.obj, extra.xml; p/meshes/c.dae), as zip, tar and tar.gz, plus a binary STL, a
few broken variants and a zip bomb. Standard library only. Run from anywhere:
    python3 fuzz/make_asset_seeds.py
"""
import gzip
import io
import os
import struct
import tarfile
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "corpus", "assets_archive")

# A tetrahedron, 0.1 m on a side, outward normals.
V = [(0, 0, 0), (0.1, 0, 0), (0, 0.1, 0), (0, 0, 0.1)]
F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def stl_ascii():
    lines = ["solid tet"]
    for a, b, c in F:
        lines += ["facet normal 0 0 0", " outer loop"]
        lines += [" vertex %g %g %g" % V[i] for i in (a, b, c)]
        lines += [" endloop", "endfacet"]
    return ("\n".join(lines + ["endsolid tet"]) + "\n").encode()


def stl_binary():
    out = bytearray(b"binary tet".ljust(80, b" "))
    out += struct.pack("<I", len(F))
    for face in F:
        out += struct.pack("<3f", 0, 0, 0)
        for i in face:
            out += struct.pack("<3f", *V[i])
        out += b"\0\0"
    return bytes(out)


def obj():
    lines = ["v %g %g %g" % v for v in V] + ["f %d %d %d" % (a + 1, b + 1, c + 1) for a, b, c in F]
    return ("\n".join(lines) + "\n").encode()


def dae():
    points = " ".join("%g %g %g" % v for v in V)
    indices = " ".join("%d %d %d" % f for f in F)
    return f"""<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit meter="1"/><up_axis>Z_UP</up_axis></asset>
<library_geometries><geometry id="g"><mesh>
<source id="p"><float_array id="pa" count="12">{points}</float_array>
<technique_common><accessor source="#pa" count="4" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<triangles count="4"><input semantic="VERTEX" source="#v" offset="0"/><p>{indices}</p></triangles>
</mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="s"><node><instance_geometry url="#g"/></node></visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
""".encode()


EXTRA = b'<mujoco><option timestep="0.01"/></mujoco>\n'


def files(stl):
    return {"a.stl": stl, "meshes/b.obj": obj(), "extra.xml": EXTRA, "p/meshes/c.dae": dae()}


def as_zip(entries):
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in entries.items():
            info = zipfile.ZipInfo(name, date_time=(2026, 1, 1, 0, 0, 0))
            z.writestr(info, data, zipfile.ZIP_DEFLATED)
    return buf.getvalue()


def as_tar(entries):
    buf = io.BytesIO()
    with tarfile.open(fileobj=buf, mode="w", format=tarfile.USTAR_FORMAT) as t:
        for name, data in entries.items():
            info = tarfile.TarInfo(name)
            info.size = len(data)
            info.mtime = 0
            t.addfile(info, io.BytesIO(data))
    return buf.getvalue()


def main():
    os.makedirs(OUT, exist_ok=True)
    seeds = {
        "all.zip": as_zip(files(stl_ascii())),
        "all.tar": as_tar(files(stl_binary())),
        "all.tar.gz": gzip.compress(as_tar(files(stl_ascii())), mtime=0),
        "mjcf_only.zip": as_zip({k: v for k, v in files(stl_binary()).items() if "c.dae" not in k}),
        "urdf_only.tar": as_tar({"p/meshes/c.dae": dae()}),
        "dotdot.tar": as_tar({"../a.stl": stl_ascii()}),
        "truncated.zip": as_zip(files(stl_ascii()))[:200],
        # A decompression bomb: 80 MiB of zeros in 80 KB, over the 64 MiB the server
        # inflates (tests/tests/alloc_bounds.rs measures what it costs).
        "bomb.zip": as_zip({"a.stl": bytes(80 << 20)}),
    }
    for name, data in seeds.items():
        with open(os.path.join(OUT, name), "wb") as f:
            f.write(data)
    print(f"wrote {len(seeds)} seeds to {OUT}")


if __name__ == "__main__":
    main()
