#!/usr/bin/env bash
# Static copies of a report for e-mail (--report-pdf, --report-png): the browser is started
# without a shell, under a time limit, and its copies join the command's outputs (all or none).
# Stand-in browsers (small scripts) check the failure paths and the arguments; Debian's chromium,
# when installed, makes real copies, checked with poppler-utils (pdfimages, pdftoppm) as the
# browser test does. Needs MTCAL, EXAMPLES.
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
RTL="$EXAMPLES/../instruments/x-axis.rtl"
outputs_absent() { [ ! -e "$tmp/r.html" ] && [ ! -e "$tmp/r.pdf" ] && [ -z "$(ls -A "$tmp/png" 2>/dev/null)" ] && ok || bad "$1: an output was left: $(ls -R "$tmp")"; }
mkdir "$tmp/png"

# No browser installed: one line naming what was looked for, nothing written, before any work.
mkdir -p "$tmp/emptybin"
expect_error "no chromium" "headless Chromium, which is not installed: no chromium, chromium-browser" -- \
  env -u MTCAL_CHROMIUM PATH="$tmp/emptybin" "$MTCAL" iso230-2 "$RTL" --report "$tmp/r.html" --report-pdf "$tmp/r.pdf"
outputs_absent "no chromium"
expect_error "MTCAL_CHROMIUM not a program" "MTCAL_CHROMIUM names '$tmp/none'" -- \
  env MTCAL_CHROMIUM="$tmp/none" "$MTCAL" iso230-2 "$RTL" --report "$tmp/r.html" --report-png "$tmp/png"
outputs_absent "bad MTCAL_CHROMIUM"
expect_error "pdf without report" "--report-pdf: expected --report FILE.html beside it" -- "$MTCAL" iso230-2 "$RTL" --report-pdf "$tmp/r.pdf"
# A folder that is not there is made (issue 29), in a folder that is: a mistyped path is refused
# before any work, and nothing is made.
expect_error "png folder's parent missing" "--report-png: expected a directory for the plot images (a new one is made in an existing folder), found that the folder '$tmp/nodir' does not exist" -- \
  "$MTCAL" iso230-2 "$RTL" --report "$tmp/r.html" --report-png "$tmp/nodir/png"
[ ! -e "$tmp/nodir" ] && outputs_absent "png folder's parent missing" || bad "the missing folder was made"
: >"$tmp/afile"
expect_error "png folder is a file" "--report-png: expected a directory for the plot images, found a file" -- \
  "$MTCAL" iso230-2 "$RTL" --report "$tmp/r.html" --report-png "$tmp/afile"
outputs_absent "png folder is a file"
expect_error "pdf is the report" "names the same file as --report" -- \
  "$MTCAL" iso230-2 "$RTL" --report "$tmp/r.html" --report-pdf "$tmp/r.html"

# Stand-in browsers.
fake() { printf '#!/bin/sh\n%s\n' "$2" >"$tmp/$1"; chmod +x "$tmp/$1"; }
fake hang 'sleep 60'
start=$(date +%s)
expect_error "timeout" "did not finish in 1 s" -- \
  env MTCAL_CHROMIUM="$tmp/hang" "$MTCAL" iso230-2 "$RTL" --report "$tmp/r.html" --report-pdf "$tmp/r.pdf" --browser-timeout 1
[ $(($(date +%s) - start)) -lt 15 ] && ok || bad "the time limit did not stop the browser"
outputs_absent "timeout"
fake fails 'echo "first line" >&2; echo "no display found" >&2; exit 3'
expect_error "browser fails" "failed (exit 3): no display found" -- \
  env MTCAL_CHROMIUM="$tmp/fails" "$MTCAL" iso230-2 "$RTL" --report "$tmp/r.html" --report-pdf "$tmp/r.pdf"
outputs_absent "browser fails"
# Writes whatever it is asked to print to, but not a PDF.
fake notpdf 'for a; do case "$a" in --print-to-pdf=*) echo hello >"${a#--print-to-pdf=}";; esac; done'
expect_error "not a PDF" "wrote a file that is not a PDF" -- \
  env MTCAL_CHROMIUM="$tmp/notpdf" "$MTCAL" iso230-2 "$RTL" --report "$tmp/r.html" --report-pdf "$tmp/r.pdf"
outputs_absent "not a PDF"
# Records its arguments (one a line: no shell split or joined them) and writes a PDF.
cat >"$tmp/args" <<SH
#!/bin/sh
for a; do printf '%s\\n' "\$a"; done >"$tmp/args.txt"
for a; do case "\$a" in --print-to-pdf=*) printf '%%PDF-1.4 stand-in' >"\${a#--print-to-pdf=}";; esac; done
SH
chmod +x "$tmp/args"
expect_exit 0 "stand-in PDF" -- env MTCAL_CHROMIUM="$tmp/args" "$MTCAL" iso230-2 "$RTL" --report "$tmp/r.html" --report-pdf "$tmp/r.pdf"
[ "$(cat "$tmp/r.pdf")" = "%PDF-1.4 stand-in" ] && [ -s "$tmp/r.html" ] && ok || bad "stand-in PDF not written beside the report"
grep -qx -- "--headless" "$tmp/args.txt" && grep -qx -- "--no-sandbox" "$tmp/args.txt" && grep -q '^--print-to-pdf=.*/report.pdf$' "$tmp/args.txt" \
  && grep -q '^file:///.*/report.html$' "$tmp/args.txt" && ok || bad "browser arguments: $(cat "$tmp/args.txt")"
rm -f "$tmp/r.html" "$tmp/r.pdf"
# --dump-dom: a page with one plot image (a 1x1 PNG) gives one PNG file, byte for byte.
png64=iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8DwHwAFBQIAX8jx0gAAAABJRU5ErkJggg==
fake dom "echo '<html><body><div class=\"plot\"></div><img class=\"plot-print\" alt=\"x\" src=\"data:image/png;base64,$png64\"></body></html>'"
expect_exit 0 "stand-in PNG" -- env MTCAL_CHROMIUM="$tmp/dom" "$MTCAL" iso230-2 "$RTL" --report "$tmp/r.html" --report-png "$tmp/png"
cmp -s "$tmp/png/r-plot-1.png" <(printf '%s' "$png64" | base64 -d) && ok || bad "PNG copy: $(ls -l "$tmp/png" 2>&1)"
rm -rf "$tmp/r.html" "$tmp/png"/*
# A folder that is not there is made with the images (as compensate --out makes its folder)...
expect_exit 0 "stand-in PNG, new folder" -- env MTCAL_CHROMIUM="$tmp/dom" "$MTCAL" iso230-2 "$RTL" --report "$tmp/r.html" \
  --report-png "$tmp/newpng/"
cmp -s "$tmp/newpng/r-plot-1.png" <(printf '%s' "$png64" | base64 -d) && ok || bad "PNG copy in a new folder: $(ls -l "$tmp" 2>&1)"
rm -rf "$tmp/r.html" "$tmp/newpng"
# ... and goes again, with its images, when the command fails after writing them (here: its
# standard output is closed, which is found when the results are flushed, after the work).
env MTCAL_CHROMIUM="$tmp/dom" "$MTCAL" iso230-2 "$RTL" --report "$tmp/r.html" --report-png "$tmp/newpng" >&- 2>"$tmp/err"
rc=$?
[ "$rc" -ne 0 ] && grep -qF "cannot write the results to standard output" "$tmp/err" && ok || bad "closed stdout: exit $rc, $(cat "$tmp/err")"
[ ! -e "$tmp/newpng" ] && outputs_absent "new folder of a failed command" || bad "the new folder of a failed command was left: $(ls -R "$tmp/newpng")"
# A page whose images were not all made: an error, no outputs.
fake nodom "echo '<html><body>no images</body></html>'"
expect_error "no plot images" "the browser made 0 of the report's 1 plot images" -- \
  env MTCAL_CHROMIUM="$tmp/nodom" "$MTCAL" iso230-2 "$RTL" --report "$tmp/r.html" --report-png "$tmp/png"
outputs_absent "no plot images"

# Debian's chromium: a real PDF whose plot is an embedded, non-blank image, and the PNG copy.
if [ -x /usr/bin/chromium ] && command -v pdfimages >/dev/null && command -v pdftoppm >/dev/null; then
  expect_exit 0 "chromium copies" -- env MTCAL_CHROMIUM=/usr/bin/chromium "$MTCAL" iso230-2 "$RTL" --report "$tmp/r.html" \
    --report-pdf "$tmp/r.pdf" --report-png "$tmp/png"
  mkdir -p "$tmp/pdf"
  pdfimages -png "$tmp/r.pdf" "$tmp/pdf/img" && pdftoppm -r 40 -png "$tmp/r.pdf" "$tmp/pdf/page"
  python3 - "$tmp/pdf" "$tmp/png/r-plot-1.png" <<'PY' && ok || bad "chromium copies are blank or missing"
import glob, struct, subprocess, sys, zlib
def png_pixels(path):
    # Decodes an 8-bit RGB/RGBA, non-interlaced PNG (what Chromium and pdfimages write).
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, colour = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and colour in (2, 6), (path, depth, colour)
            bpp = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, stride, rows, prev = zlib.decompress(idat), w * bpp, [], bytearray(w * bpp)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            p = a + b - c
            pred = [0, a, b, (a + b) // 2, a if abs(p - a) <= abs(p - b) and abs(p - a) <= abs(p - c) else (b if abs(p - b) <= abs(p - c) else c)][f]
            line[i] = (line[i] + pred) & 0xFF
        rows.append(line)
        prev = line
    return w, h, bpp, rows
def coloured_share(path):
    w, h, bpp, rows = png_pixels(path)
    n = c = 0
    for line in rows[::3]:
        for x in range(0, w, 3):
            r, g, b = line[x * bpp:x * bpp + 3]
            n += 1
            c += max(r, g, b) - min(r, g, b) > 60
    return w, c / n
d = sys.argv[1]
imgs = sorted(glob.glob(d + "/img-*.png"))
pages = sorted(glob.glob(d + "/page-*.png"))
shares = [coloured_share(p)[1] for p in imgs]
assert sum(s > 0.0005 for s in shares) >= 1, ("no coloured plot image in the PDF", shares)
assert any(coloured_share(p)[1] > 0.001 for p in pages), "no page with the plot's colours"
w, s = coloured_share(sys.argv[2])
assert w >= 1000 and s > 0.0005, ("PNG copy", w, s)
print(f"PDF: {len(pages)} pages, {len(imgs)} images, coloured shares {[round(x, 4) for x in shares]}; PNG {w} px wide, {s:.4f} coloured")
PY
else
  echo "note: /usr/bin/chromium or poppler-utils not installed: real copies not checked here (reports_in_browser checks printing)"
fi
summary_and_exit
