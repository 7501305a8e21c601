"""The reference copy: report.md and the figures it links, copied with their relative paths."""

import os
import re
import shutil


def publish(report_path, dest):
    """Copies the report and the figures it links into dest, keeping their paths relative to
    the report (so the links work unchanged); figures no longer linked are removed."""
    os.makedirs(dest, exist_ok=True)
    with open(report_path) as f:
        text = f.read()
    linked = set(re.findall(r"!\[[^\]]*\]\(([^)]+\.png)\)", text))
    for rel_path in linked:
        src = os.path.join(os.path.dirname(report_path), rel_path)
        dst = os.path.join(dest, rel_path)
        os.makedirs(os.path.dirname(dst), exist_ok=True)
        shutil.copyfile(src, dst)
    for root, _, files in os.walk(dest):
        for name in files:
            rel_path = os.path.relpath(os.path.join(root, name), dest)
            if name.endswith(".png") and rel_path not in linked:
                os.remove(os.path.join(root, name))
    with open(os.path.join(dest, "report.md"), "w") as f:
        f.write(text)
    print(f"published {dest}/report.md")
