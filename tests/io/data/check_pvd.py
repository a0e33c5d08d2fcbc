"""Parses a .pvd with xml.etree and prints its datasets, one per line:

    COUNT <n>
    DATASET <repr(float(timestep))> <part> <group> <file>

Exits 1 (with the reason) when the file is not a well-formed VTK Collection.
"""
import sys
import xml.etree.ElementTree as ET


def main():
    root = ET.parse(sys.argv[1]).getroot()
    if root.tag != "VTKFile" or root.get("type") != "Collection":
        print(f"not a VTK collection: <{root.tag} type={root.get('type')!r}>")
        return 1
    coll = root.findall("Collection")
    if len(coll) != 1:
        print(f"{len(coll)} <Collection> elements")
        return 1
    sets = list(coll[0])
    print(f"COUNT {len(sets)}")
    for d in sets:
        if d.tag != "DataSet":
            print(f"unexpected element <{d.tag}>")
            return 1
        print(f"DATASET {float(d.get('timestep'))!r} {int(d.get('part'))} "
              f"[{d.get('group')}] {d.get('file')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
