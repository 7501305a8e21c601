"""The reference copy: report.md, its appendices (appendix/*.md) and the figures they link,
copied with their relative paths, and the data behind them (each study's summary.json, its sweep
tables gzip-compressed, their recorded commands, the seeded study's table), so that
scwexp.results.load can re-analyse the copy without running scw."""

import glob
import gzip
import os
import re
import shutil

_PAGE = re.compile(r"\]\(([^)#]+\.md)\)")
_IMAGE = re.compile(r"!\[[^\]]*\]\(([^)]+\.png)\)")


def _figures(root, page):
    """The figures `page` (a path relative to root) links, as paths relative to root."""
    with open(os.path.join(root, page)) as f:
        return [os.path.normpath(os.path.join(os.path.dirname(page), t))
                for t in _IMAGE.findall(f.read())]


def publish(report_path, dest, appendix="appendix"):
    """Copies the report, its appendices and the figures they link into dest, keeping their
    paths relative to the report (so the links work unchanged); figures no page in dest links
    and appendices no longer made are removed."""
    src_root = os.path.dirname(report_path)
    os.makedirs(os.path.join(dest, appendix), exist_ok=True)
    pages = ["report.md"] + sorted(
        os.path.relpath(p, src_root) for p in glob.glob(os.path.join(src_root, appendix, "*.md")))
    linked = set()
    for page in pages:
        for rel_path in _figures(src_root, page):
            dst = os.path.join(dest, rel_path)
            os.makedirs(os.path.dirname(dst), exist_ok=True)
            shutil.copyfile(os.path.join(src_root, rel_path), dst)
            linked.add(rel_path)
    # Figures of other pages kept in dest (e.g. maneuvers.md) stay: they are linked too.
    for root, _, files in os.walk(dest):
        for name in files:
            rel_md = os.path.relpath(os.path.join(root, name), dest)
            if name.endswith(".md") and rel_md not in pages \
                    and os.path.dirname(rel_md) != appendix:
                linked.update(_figures(dest, rel_md))
    for root, _, files in os.walk(dest):
        for name in files:
            rel_path = os.path.relpath(os.path.join(root, name), dest)
            if name.endswith(".png") and rel_path not in linked:
                os.remove(os.path.join(root, name))
            elif name.endswith(".md") and os.path.dirname(rel_path) == appendix \
                    and rel_path not in pages:
                os.remove(os.path.join(root, name))
    for page in pages:
        shutil.copyfile(os.path.join(src_root, page), os.path.join(dest, page))
    # Other pages the report links (e.g. ocd/crossval.md), where the results tree has them.
    with open(os.path.join(src_root, "report.md")) as f:
        for target in _PAGE.findall(f.read()):
            rel_path = os.path.normpath(target)
            if rel_path not in pages and os.path.exists(os.path.join(src_root, rel_path)):
                os.makedirs(os.path.dirname(os.path.join(dest, rel_path)), exist_ok=True)
                shutil.copyfile(os.path.join(src_root, rel_path), os.path.join(dest, rel_path))
    files = copy_data(src_root, dest)
    print(f"published {dest}/report.md, {len(pages) - 1} appendices and {files} data files")


DATA = ("summary.json", "sweep*.csv", "sweep*.csv.gz", "sweep*.csv.cmd", "seeded.md")


def copy_data(src_root, dest):
    """Copies every study folder's data under columns/ (DATA), a plain sweep table compressed
    (.csv.gz, no time stamp: the same table gives the same bytes); returns the files copied."""
    n = 0
    for study in sorted(glob.glob(os.path.join(src_root, "columns", "*", "*", "summary.json"))):
        d = os.path.dirname(study)
        out = os.path.join(dest, os.path.relpath(d, src_root))
        os.makedirs(out, exist_ok=True)
        for pattern in DATA:
            for path in sorted(glob.glob(os.path.join(d, pattern))):
                name = os.path.basename(path)
                if name.endswith(".csv"):
                    with open(path, "rb") as src, gzip.GzipFile(
                            os.path.join(out, name + ".gz"), "wb", mtime=0) as dst:
                        shutil.copyfileobj(src, dst)
                else:
                    shutil.copyfile(path, os.path.join(out, name))
                n += 1
    return n
