"""Reads a probe CSV with Python's csv module and prints what it read:

    HEADER <name>|<name>|...
    ROW <repr(float)> <repr(float)> ...

Exits 1 when a row has a different number of fields than the header.
"""
import csv
import sys


def main():
    with open(sys.argv[1], newline="") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    print("HEADER " + "|".join(header))
    for i, row in enumerate(rows[1:]):
        if len(row) != len(header):
            print(f"row {i + 1} has {len(row)} fields, header has {len(header)}")
            return 1
        print("ROW " + " ".join(repr(float(v)) for v in row))
    return 0


if __name__ == "__main__":
    sys.exit(main())
