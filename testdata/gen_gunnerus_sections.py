#!/usr/bin/env python3
"""Write the R/V Gunnerus offset table as a sections CSV (`section,x,y,z`, one row per point).

Usage: python3 testdata/gen_gunnerus_sections.py testdata/gunnerus_offsets.csv > testdata/gunnerus_sections.csv

The same points as the table (provenance in testdata/README.md), in the form the kernel's
tests read without knowing offset tables: each station a section, labelled by its index,
its points bottom to top (table rows in order), empty cells skipped. The decimal text of the
table is copied as it stands, so both files give the same f64 values.
"""
import sys


def main(path: str) -> None:
    rows = [line.rstrip("\n").split(",") for line in open(path) if line.strip()]
    xs = rows[0][1:]
    print("section,x,y,z")
    for k, x in enumerate(xs):
        for row in rows[1:]:
            cell = row[1 + k].strip()
            if cell:
                print(f"{k},{x.strip()},{cell},{row[0].strip()}")


if __name__ == "__main__":
    main(sys.argv[1])
