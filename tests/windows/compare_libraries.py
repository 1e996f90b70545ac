"""Compares two .mwb libraries of one run made by different engine builds.

Each library records the engine build that sampled it (compiler, ODE build, ...), so the files
differ there and in the header's checksum. Everything else must be byte for byte the same: the
header's JSON with the engine build left out (scene, parameters, codec bounds, seed), and every
record (world motion, contacts, checkpoints, metrics), in the same order.

With --within, A is a run cut short (cancelled): every record of A must be whole and be, byte for
byte, B's record of the same world (B may hold more worlds, in any order).

    python3 compare_libraries.py A.mwb B.mwb            exit 0 when the same, 1 with the first difference
    python3 compare_libraries.py --within A.mwb B.mwb   exit 0 when B holds each of A's records
"""
import json
import struct
import sys

MAGIC = b"\x89MWB\r\n\x1a\n"
# native/core/library/LibraryFormat.h: a record's header is magic, type, version, payload size and
# crc32; the payload of a world (type 1) or a rejection (type 2) starts with the world's index.
RECORD_MAGIC = 0x4352574D
RECORD_HEADER_BYTES = 20
WORLD_RECORD_TYPES = (1, 2)


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


def split_records(path, records):
    """[(type, world index or None, the record's bytes)] in file order; anything that is not a
    whole record (a torn last one) ends the comparison."""
    found, offset = [], 0
    while offset < len(records):
        if len(records) - offset < RECORD_HEADER_BYTES:
            raise SystemExit(f"{path}: a torn record at byte {offset} of the records")
        magic, kind, _version, size = struct.unpack_from("<IIII", records, offset)
        end = offset + RECORD_HEADER_BYTES + size
        if magic != RECORD_MAGIC or end > len(records):
            raise SystemExit(f"{path}: no whole record at byte {offset} of the records")
        world = None
        if kind in WORLD_RECORD_TYPES:
            world = struct.unpack_from("<Q", records, offset + RECORD_HEADER_BYTES)[0]
        found.append((kind, world, records[offset:end]))
        offset = end
    return found


def compare_within(path_a, records_a, path_b, records_b):
    """Exit status: 0 when each record of A is B's record of the same world, byte for byte."""
    theirs = {(kind, world): record for kind, world, record in split_records(path_b, records_b)
              if world is not None}
    ours = split_records(path_a, records_a)
    for number, (kind, world, record) in enumerate(ours):
        if world is None:
            print(f"record {number} of {path_a} is of type {kind}, not a world's")
            return 1
        if theirs.get((kind, world)) != record:
            missing = (kind, world) not in theirs
            print(f"record {number} of {path_a} (world {world}) "
                  + ("is not in " if missing else "differs from that of ") + path_b)
            return 1
    worlds = sorted(world for _, world, _ in ours)
    print(f"same run header; each of the {len(ours)} records of {path_a} (worlds {worlds[0] if worlds else '-'} "
          f"to {worlds[-1] if worlds else '-'}) is whole and the same bytes in {path_b}")
    return 0


def main(arguments):
    within = "--within" in arguments
    path_a, path_b = [a for a in arguments if a != "--within"][:2]
    header_a, build_a, records_a = read_library(path_a)
    header_b, build_b, records_b = read_library(path_b)
    print(f"{path_a}: made by {build_a}")
    print(f"{path_b}: made by {build_b}")
    if header_a != header_b:
        keys = sorted(k for k in set(header_a) | set(header_b) if header_a.get(k) != header_b.get(k))
        print(f"headers differ beyond the engine build: {', '.join(keys)}")
        return 1
    if within:
        return compare_within(path_a, records_a, path_b, records_b)
    if records_a != records_b:
        number, world, offset = first_record_difference(records_a, records_b)
        print(f"records differ: {len(records_a)} and {len(records_b)} bytes, first in record {number} "
              f"(world {world}) at byte {offset} of the records")
        return 1
    print(f"same run header and the same {len(records_a)} bytes of records")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
