#!/usr/bin/env python3
"""Regenerates the app's two fonts in assets/fonts/ from egui's default fonts.

egui's `default_fonts` feature embeds Ubuntu-Light (362 kB) and Hack (309 kB) whole in the
wasm, about 320 kB of the gzip download. The app needs only the scripts and symbols listed
below, so it embeds subsets of the two instead (src/app/fonts.rs), without TrueType hinting
instructions (egui's rasteriser, skrifa, then hints the outlines itself), renamed as their
licences ask of modified versions, each beside its licence text.

The sources are the fonts of the epaint_default_fonts 0.37.0 crate (cargo fetches it into its
registry when it is not there); fontTools comes from PyPI into a virtual environment under
target/fonts-venv.

    scripts/subset-fonts.py
"""
import glob
import os
import shutil
import subprocess
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
VENV = os.path.join(ROOT, "target", "fonts-venv")
OUT = os.path.join(ROOT, "assets", "fonts")
FONTTOOLS = "fonttools==4.68.0"

# Text of the app (Latin with European accents, Greek for the symbols of the docs' formulas,
# Cyrillic for scene names) and the punctuation, arrows, super- and subscripts, mathematical
# and technical symbols its labels print (µm, °, ×, ±, −, ≤, ≥, ·, √, ′, ″, →, …).
PROPORTIONAL = [
    "U+0020-007E",  # ASCII
    "U+00A0-017F",  # Latin-1 Supplement, Latin Extended-A
    "U+0218-021B",  # Ș ș Ț ț
    "U+02C6-02DD",  # spacing modifiers (ˆ ˇ ˘ ˙ ˚ ˛ ˜ ˝)
    "U+0370-03FF",  # Greek
    "U+0400-045F",  # Cyrillic
    "U+2000-206F",  # general punctuation (– — ‘ ’ “ ” • … ′ ″ ‰)
    "U+2070-209F",  # superscripts and subscripts
    "U+20AC",  # €
    "U+2100-214F",  # letterlike symbols (№ ™ Ω ℓ)
    "U+2190-21FF",  # arrows
    "U+2200-22FF",  # mathematical operators (− √ ∞ ≈ ≠ ≤ ≥ ∂ ∑)
    "U+2300-23FF",  # miscellaneous technical (⌀)
    "U+25A0-25FF",  # geometric shapes (■ ▲ ● ◆)
    "U+FFFD",  # replacement character
]
# Program text, numbers and code: ASCII and Latin-1 in Hack; anything else falls back to
# Ubuntu (src/app/fonts.rs), and Hack is in turn the proportional family's fallback for the
# few symbols Ubuntu lacks (′ ″ → …).
MONOSPACE = ["U+0020-007E", "U+00A0-00FF", "U+2010-2027", "U+2030-2033", "U+2190-2193", "U+2212", "U+2260", "U+2264-2265", "U+FFFD"]

FONTS = [
    # (source, output, unicodes, new family name, licence files)
    ("Ubuntu-Light.ttf", "Ubuntu-Light-derivative-interpolab.ttf", PROPORTIONAL, "Ubuntu Light derivative interpolab", ["UFL.txt"]),
    ("Hack-Regular.ttf", "Hack-Regular-interpolab-subset.ttf", MONOSPACE, "Hack interpolab subset", ["Hack-Regular.txt"]),
]


def ensure_venv():
    py = os.path.join(VENV, "bin", "python")
    if os.path.realpath(sys.prefix) == os.path.realpath(VENV):
        return
    if not os.path.exists(py):
        subprocess.run([sys.executable, "-m", "venv", VENV], check=True)
    if subprocess.run([py, "-c", "import fontTools.subset"], capture_output=True).returncode != 0:
        subprocess.run([py, "-m", "pip", "install", "--quiet", FONTTOOLS], check=True)
    os.execv(py, [py, os.path.abspath(__file__)] + sys.argv[1:])


def main():
    ensure_venv()
    from fontTools import subset
    from fontTools.ttLib import TTFont

    pattern = os.path.join(os.environ.get("CARGO_HOME", os.path.expanduser("~/.cargo")), "registry", "src", "*",
                           "epaint_default_fonts-0.37.0", "fonts")
    if not glob.glob(pattern):
        # The app no longer depends on the crate: let cargo fetch it for a throwaway manifest.
        tmp = os.path.join(ROOT, "target", "fonts-src")
        os.makedirs(os.path.join(tmp, "src"), exist_ok=True)
        with open(os.path.join(tmp, "Cargo.toml"), "w") as fh:
            fh.write('[package]\nname = "fonts-src"\nversion = "0.0.0"\nedition = "2021"\n\n'
                     '[dependencies]\nepaint_default_fonts = "=0.37.0"\n')
        with open(os.path.join(tmp, "src", "lib.rs"), "w") as fh:
            fh.write("")
        subprocess.run(["cargo", "fetch", "--manifest-path", os.path.join(tmp, "Cargo.toml")], check=True)
    src = sorted(glob.glob(pattern))[-1]
    os.makedirs(OUT, exist_ok=True)
    for source, output, unicodes, family, licences in FONTS:
        opts = subset.Options()
        opts.hinting = False  # no TrueType instructions: skrifa auto-hints
        opts.desubroutinize = True
        opts.layout_features = ["kern", "liga", "calt", "ccmp", "locl", "mark", "mkmk"]
        opts.name_IDs = [0, 1, 2, 3, 4, 5, 6, 13, 14]  # copyright, names, version, licence
        opts.name_languages = [0x409]
        opts.notdef_outline = True
        # The original timestamp kept: the same input gives the same bytes.
        font = TTFont(os.path.join(src, source), recalcTimestamp=False)
        sub = subset.Subsetter(opts)
        sub.populate(unicodes=subset.parse_unicodes(",".join(u.replace("U+", "") for u in unicodes)))
        sub.subset(font)
        # Both licences ask a modified font to carry a name of its own (UFL 1.0 §2c: the
        # original name with "derivative X" appended).
        ps = family.replace(" ", "")
        for rec in font["name"].names:
            if rec.nameID in (1, 16):
                rec.string = family
            elif rec.nameID in (4, 18):
                rec.string = family
            elif rec.nameID == 6:
                rec.string = ps
            elif rec.nameID == 3:
                rec.string = f"{ps}; subset by interpolab scripts/subset-fonts.py"
        path = os.path.join(OUT, output)
        font.save(path)
        for lic in licences:
            shutil.copy(os.path.join(src, lic), os.path.join(OUT, lic))
        print(f"{output}: {os.path.getsize(os.path.join(src, source))} → {os.path.getsize(path)} bytes, "
              f"{len(TTFont(path).getBestCmap())} characters")


if __name__ == "__main__":
    main()
