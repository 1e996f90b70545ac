"""Compares two .mwb libraries of one run made by different engine builds.

Each library records the engine build that sampled it (compiler, ODE build, ...), so the files
differ there and in the header's checksum. Everything else must be byte for byte the same: the
header's JSON with the engine build left out (scene, parameters, codec bounds, seed), and every
record (world motion, contacts, checkpoints, metrics), in the same order.

    python3 compare_libraries.py A.mwb B.mwb     exit 0 when the same, 1 with the first difference
"""
import json
import struct
import sys

MAGIC = b"\x89MWB\r\n\x1a\n"


def read_library(path):
    data = open(path, "rb").read()
    if data[:8] != MAGIC:
        raise SystemExit(f"{path}: not a library file")
    _version, size = struct.unpack_from("<II", data, 8)
    header = json.loads(data[16:16 + size])
    build = header.pop("engine", None)
    records = data[16 + size + 4:]
    return header, build, records


def first_record_difference(a, b):
    """(record number, world index or None, byte offset in the records) of the first difference."""
    offset, number = 0, 0
    while offset < min(len(a), len(b)):
        size = struct.unpack_from("<I", a, offset + 12)[0] + 20
        if a[offset:offset + size] != b[offset:offset + size]:
            world = struct.unpack_from("<Q", a, offset + 20)[0] if size >= 28 else None
            return number, world, offset
        offset, number = offset + size, number + 1
    return number, None, offset


def main(path_a, path_b):
    header_a, build_a, records_a = read_library(path_a)
    header_b, build_b, records_b = read_library(path_b)
    print(f"{path_a}: made by {build_a}")
    print(f"{path_b}: made by {build_b}")
    if header_a != header_b:
        keys = sorted(k for k in set(header_a) | set(header_b) if header_a.get(k) != header_b.get(k))
        print(f"headers differ beyond the engine build: {', '.join(keys)}")
        return 1
    if records_a != records_b:
        number, world, offset = first_record_difference(records_a, records_b)
        print(f"records differ: {len(records_a)} and {len(records_b)} bytes, first in record {number} "
              f"(world {world}) at byte {offset} of the records")
        return 1
    print(f"same run header and the same {len(records_a)} bytes of records")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:3]))
