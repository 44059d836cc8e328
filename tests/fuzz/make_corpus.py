#!/usr/bin/env python3
"""Writes the fuzz targets' seed corpus (corpus/<target>/): small valid files of every form
each reader accepts. Run from anywhere; it rewrites the folders beside it."""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))

# a unit square split in two, a tetrahedron's worth of quads: small and valid
VERTS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 0.5, 1.25)]
TRIS = [(0, 1, 2), (0, 2, 3), (0, 1, 4)]
QUAD = (0, 1, 2, 3)


def write(target, name, data):
    folder = os.path.join(HERE, "corpus", target)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def obj_seeds():
    v = "".join("v %g %g %g\n" % p for p in VERTS)
    write("obj", "triangles.obj", v + "".join("f %d %d %d\n" % tuple(i + 1 for i in t) for t in TRIS))
    write("obj", "crlf_forms.obj",
          ("# comment\r\no thing\r\n" + v.replace("\n", "\r\n") + "vt 0 0\r\nvn 0 0 1\r\n"
           "f 1/1 2/1 3/1\r\nf 1//1 3//1 4//1\r\nf -5 -4 -1 # relative\r\n"))
    write("obj", "cr_only_quad.obj", v.replace("\n", "\r") + "f 1 2 3 4\r")
    write("obj", "w_and_colours.obj",
          "v 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0\ng g\ns off\nusemtl m\nf 1 2 3\nl 1 2\n")
    write("obj", "points.obj", "v 1e-300 -2.5e+30 3\nv 4 5 6")


def ply_header(fmt, nv, nf, vtype="float", itype="int", extra=""):
    return ("ply\nformat %s 1.0\ncomment seed\nelement vertex %d\n"
            "property %s x\nproperty %s y\nproperty %s z\n%s"
            "element face %d\nproperty list uchar %s vertex_indices\nend_header\n"
            % (fmt, nv, vtype, vtype, vtype, extra, nf, itype))


def ply_seeds():
    faces = TRIS + [QUAD]
    body = "".join("%g %g %g\n" % p for p in VERTS) + "".join(
        "%d %s\n" % (len(f), " ".join(map(str, f))) for f in faces)
    write("ply", "ascii.ply", ply_header("ascii", len(VERTS), len(faces)) + body)
    write("ply", "ascii_crlf.ply", (ply_header("ascii", len(VERTS), len(faces)) + body).replace("\n", "\r\n"))
    for fmt, end, vtype, code, itype, icode in [
            ("binary_little_endian", "<", "float", "f", "int", "i"),
            ("binary_big_endian", ">", "double", "d", "uint", "I"),
            ("binary_little_endian", "<", "double", "d", "ushort", "H"),
            ("binary_big_endian", ">", "float", "f", "uchar", "B")]:
        data = ply_header(fmt, len(VERTS), len(faces), vtype, itype).encode()
        for p in VERTS:
            data += struct.pack(end + code * 3, *p)
        for f in faces:
            data += struct.pack(end + "B" + icode * len(f), len(f), *f)
        write("ply", "%s_%s_%s.ply" % (fmt.split("_")[1], vtype, itype), data)
    # extra properties and an extra element with a list, before and after the faces
    extra = "property uchar red\nproperty list uchar float weights\n"
    data = ("ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
            "property float z\n" + extra + "element face 1\nproperty list uchar int vertex_indices\n"
            "element edge 1\nproperty int a\nproperty int b\nend_header\n").encode()
    for i, p in enumerate(VERTS[:3]):
        data += struct.pack("<fffBB2f", *p, 7, 2, 0.5, 0.25)
    data += struct.pack("<B3i", 3, 0, 1, 2) + struct.pack("<2i", 0, 1)
    write("ply", "little_extras.ply", data)
    # header lines ended by a lone CR; the first data byte is a LF (x = 1 + 10 ulp, little-endian)
    data = ply_header("binary_little_endian", 3, 1, "double", "int").replace("\n", "\r").encode()
    data += struct.pack("<Q", 0x3FF000000000000A) + struct.pack("<8d", 0, 0, 1, 0, 0, 0, 1, 0)
    data += struct.pack("<B3i", 3, 0, 1, 2)
    write("ply", "little_cr_only.ply", data)


def csv_seeds():
    rows7 = ["1,2,-1,4,0,1,1", "3,8,1,1,5,16,1", "0,1,0,1,1,1,1", "-7,8,1,2,3,4,1"] * 2
    write("query_csv", "seven_columns.csv", "\n".join(rows7) + "\n")
    rows6 = ["%d,%d,1,1,-3,2" % (i, 1 << (i + 10)) for i in range(8)]
    write("query_csv", "six_columns_crlf.csv", "\r\n".join(rows6) + "\r\n")
    big = ["6004799503160661,36028797018963968,1,1267650600228229401496703205376,"
           "3541774862152233910272,2361183241434822606848,0"] * 8
    write("query_csv", "long_integers.csv", "\n".join(big))
    write("query_csv", "cr_only.csv", "\r".join(rows7) + "\r")


def truth_seeds():
    write("toi_truth", "pairs.bin", b"[[0, 17], [3, 20], [5, 22]]\0[true, false, true]")
    write("toi_truth", "empty.bin", b"[]\0[]")
    write("toi_truth", "spaced.bin", b" [ [4294967295,0] ]\r\n\0\t[false]\r\n")


if __name__ == "__main__":
    obj_seeds()
    ply_seeds()
    csv_seeds()
    truth_seeds()
