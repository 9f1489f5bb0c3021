#!/usr/bin/python3
"""Builds the tiny test fonts of the feature-curve input tests (and the font
fuzzer's seed corpus) from coordinates written here, so every expected value
in tests/features/input_font_test.cpp is known exactly and no third-party
font data is redistributed.

    /usr/bin/python3 tests/features/data/make_test_fonts.py   # Debian python3-fonttools

Outputs (1000 units per em):
  tiny-tt.ttf   TrueType (glyf, quadratic), with a 'kern' table (A,O) = -50
  tiny-cff.otf  OpenType CFF (cubic)
Glyphs: A (two line-only contours), O (TrueType: a contour of four off-curve
points only, so every on-curve point is implied; CFF: four cubics), g (a line
then two consecutive conics with an implied midpoint at odd coordinates),
space (no contours).
"""
import os
from fontTools.fontBuilder import FontBuilder
from fontTools.pens.ttGlyphPen import TTGlyphPen
from fontTools.pens.t2CharStringPen import T2CharStringPen
from fontTools.ttLib import newTable
from fontTools.ttLib.tables._k_e_r_n import KernTable_format_0

HERE = os.path.dirname(os.path.abspath(__file__))
ORDER = [".notdef", "space", "A", "O", "g"]
CMAP = {0x20: "space", 0x41: "A", 0x4F: "O", 0x67: "g"}
ADV = {".notdef": 500, "space": 250, "A": 700, "O": 650, "g": 450}


def draw_A(pen):
    pen.moveTo((0, 0)); pen.lineTo((350, 700)); pen.lineTo((700, 0)); pen.closePath()
    pen.moveTo((250, 100)); pen.lineTo((450, 100)); pen.lineTo((350, 300)); pen.closePath()


def draw_notdef(pen):
    pen.moveTo((50, 0)); pen.lineTo((450, 0)); pen.lineTo((450, 700)); pen.lineTo((50, 700)); pen.closePath()


def build_tt(path):
    fb = FontBuilder(1000, isTTF=True)
    fb.setupGlyphOrder(ORDER)
    fb.setupCharacterMap(CMAP)
    glyphs = {}
    for name in ORDER:
        pen = TTGlyphPen(None)
        if name == ".notdef":
            draw_notdef(pen)
        elif name == "A":
            draw_A(pen)
        elif name == "O":
            # All four points off-curve: implied on-curve midpoints
            # (451, 150.5), (451, 451), (150.5, 451), (150.5, 150.5).
            pen.qCurveTo((301, 0), (601, 301), (301, 601), (0, 301), None)
            pen.closePath()
        elif name == "g":
            pen.moveTo((0, 0)); pen.lineTo((200, 0))
            pen.qCurveTo((300, 0), (401, 101), (300, 200))  # implied (350.5, 50.5)
            pen.lineTo((0, 200)); pen.closePath()
        glyphs[name] = pen.glyph()
    fb.setupGlyf(glyphs)
    fb.setupHorizontalMetrics({n: (ADV[n], 0) for n in ORDER})
    fb.setupHorizontalHeader(ascent=800, descent=-200)
    fb.setupNameTable({"familyName": "SurfgradTestTT", "styleName": "Regular"})
    fb.setupOS2(sTypoAscender=800, sTypoDescender=-200, usWinAscent=800, usWinDescent=200)
    fb.setupPost()
    kern = newTable("kern")
    kern.version = 0
    sub = KernTable_format_0()
    sub.version = 0
    sub.coverage = 1
    sub.format = 0
    sub.kernTable = {("A", "O"): -50}
    kern.kernTables = [sub]
    fb.font["kern"] = kern
    fb.save(path)


def build_cff(path):
    fb = FontBuilder(1000, isTTF=False)
    fb.setupGlyphOrder(ORDER)
    fb.setupCharacterMap(CMAP)
    charstrings = {}
    for name in ORDER:
        pen = T2CharStringPen(ADV[name], None)
        if name == ".notdef":
            draw_notdef(pen)
        elif name == "A":
            draw_A(pen)
        elif name == "O":
            # Four cubics, a circle-like loop of radius 300 around (300, 300).
            k = 166
            pen.moveTo((600, 300))
            pen.curveTo((600, 300 + k), (300 + k, 600), (300, 600))
            pen.curveTo((300 - k, 600), (0, 300 + k), (0, 300))
            pen.curveTo((0, 300 - k), (300 - k, 0), (300, 0))
            pen.curveTo((300 + k, 0), (600, 300 - k), (600, 300))
            pen.closePath()
        elif name == "g":
            # An S-shaped cubic (inflection) closed by lines.
            pen.moveTo((0, 0)); pen.lineTo((100, 0))
            pen.curveTo((400, 0), (0, 400), (400, 400))
            pen.lineTo((0, 400)); pen.closePath()
        charstrings[name] = pen.getCharString()
    fb.setupCFF("SurfgradTestCFF", {"FullName": "SurfgradTestCFF"}, charstrings, {})
    fb.setupHorizontalMetrics({n: (ADV[n], 0) for n in ORDER})
    fb.setupHorizontalHeader(ascent=800, descent=-200)
    fb.setupNameTable({"familyName": "SurfgradTestCFF", "styleName": "Regular"})
    fb.setupOS2(sTypoAscender=800, sTypoDescender=-200, usWinAscent=800, usWinDescent=200)
    fb.setupPost()
    fb.save(path)


if __name__ == "__main__":
    build_tt(os.path.join(HERE, "tiny-tt.ttf"))
    build_cff(os.path.join(HERE, "tiny-cff.otf"))
