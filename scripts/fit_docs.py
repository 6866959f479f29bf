# SPDX-License-Identifier: Apache-2.0
"""Write a recorded fit (``make fit``: docs/fit_teapot.json, docs/fit_gallery.json) into the
generated block of docs/fit.md that names it.

python scripts/fit_docs.py docs/fit_teapot.json docs/fit.md
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

from model.fit import report


def main(record_path: str, page_path: str) -> int:
    record = json.loads(Path(record_path).read_text())
    page = Path(page_path)
    text = page.read_text()
    pattern = re.compile(
        re.escape(report.DOCS_BEGIN.format(record=record_path))
        + r".*?"
        + re.escape(report.DOCS_END),
        re.S,
    )
    if not pattern.search(text):
        print(f"{page}: no generated block of {record_path} to replace", file=sys.stderr)
        return 1
    block = report.docs_block(record, record_path)
    page.write_text(pattern.sub(lambda _: block, text, count=1))
    print(f"wrote the record {record_path} into {page}")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
