#!/usr/bin/env python3
"""Replaces the text between <!-- NAME begin --> and <!-- NAME end --> of DOC with
standard input, so that a script regenerates its own section of a hand-written page.

    some-generator | python3 scripts/doc_section.py docs/LOD.md lod-scans
"""
import sys

doc, name = sys.argv[1], sys.argv[2]
text = open(doc).read()
begin, end = f"<!-- {name} begin -->", f"<!-- {name} end -->"
if begin not in text or end not in text:
    sys.exit(f"{doc}: no '{begin}' ... '{end}' section")
a, b = text.index(begin) + len(begin), text.index(end)
open(doc, "w").write(text[:a] + "\n\n" + sys.stdin.read().strip("\n") + "\n\n" + text[b:])
