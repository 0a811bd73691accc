#!/usr/bin/env python3
"""Independent SVG checker for qrm's plots (Python 3 standard library only).

  check_svg.py FILE.svg [--expect-text TEXT]... [--min-count TAG=N]...

Parses the file with xml.etree.ElementTree (so it must be well-formed XML), requires an <svg>
root in the SVG namespace with positive width and height, and then optionally requires that each
TEXT occurs in the text content of some <text> or <title> element (after XML unescaping, so
escaped characters must come back exactly) and that at least N elements named TAG exist.
Exit status 0 when every check passes, 1 otherwise (with the reason on stderr).
"""
import argparse
import sys
import xml.etree.ElementTree as ET

SVG = "{http://www.w3.org/2000/svg}"


def main():
    ap = argparse.ArgumentParser(description="Check that an SVG file is well-formed and holds given texts.")
    ap.add_argument("svg")
    ap.add_argument("--expect-text", action="append", default=[])
    ap.add_argument("--min-count", action="append", default=[], metavar="TAG=N")
    args = ap.parse_args()
    try:
        root = ET.parse(args.svg).getroot()
        if root.tag != SVG + "svg":
            raise ValueError("root element is %s, not an SVG <svg>" % root.tag)
        w, h = float(root.get("width", "0")), float(root.get("height", "0"))
        if not (w > 0 and h > 0):
            raise ValueError("width/height %r x %r are not positive" % (root.get("width"), root.get("height")))
        texts = ["".join(e.itertext()) for e in root.iter() if e.tag in (SVG + "text", SVG + "title")]
        for t in args.expect_text:
            if not any(t in s for s in texts):
                raise ValueError("no text element contains %r (texts: %r)" % (t, texts[:40]))
        counts = {}
        for e in root.iter():
            tag = e.tag[len(SVG):] if e.tag.startswith(SVG) else e.tag
            counts[tag] = counts.get(tag, 0) + 1
        for spec in args.min_count:
            tag, _, n = spec.partition("=")
            if counts.get(tag, 0) < int(n):
                raise ValueError("%d <%s> element(s), expected at least %s" % (counts.get(tag, 0), tag, n))
    except (ET.ParseError, ValueError, OSError) as e:
        print("check_svg: %s: FAILED: %s" % (args.svg, e), file=sys.stderr)
        return 1
    print("check_svg: %s: OK: %gx%g, %d text elements" % (args.svg, w, h, len(texts)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
