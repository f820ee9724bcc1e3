"""The design record's dimensioned drawings laid out by measuring their text: every label inside its drawing, none
over another, ticks in millimetres on every axis; read back from the figure and from the PDF's own word boxes.
And no page of the record near-empty, read from its pages as rendered."""

from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.text import Annotation, Text
from matplotlib.transforms import Bbox

import synth
from api.translate.machine import machine_from
from mechsynth_client.schemas.common import FOURBAR_EXAMPLE
from mechsynth_client.schemas.machine import MachineIn
from synth.machine.record import DesignRecord
from synth.machine.report import design_report_pdf, dimensioned_figure

# The README's four-bar machine, fully balanced (two counterweights: the crank's and the rocker's, whose label the
# record clipped), with two helical stages sized for strength (both gear pairs drawn) and a flywheel.
BODY: dict[str, Any] = {
    "mechanism": FOURBAR_EXAMPLE, "speed_rpm": 300, "delta": 0.01,
    "loads": [{"type": "window", "torque_Nm": 40, "start_deg": 0, "end_deg": 180}],
    "drive": {"stages": ["helical", "helical"], "synchronous_rpm": 1500, "size_gears": True},
    "balancing": {"mode": "full"}}


@pytest.fixture(scope="module")
def design() -> Any:
    return synth.design_machine(machine_from(MachineIn.model_validate(BODY), 4))


def _apart(a: Bbox, b: Bbox) -> bool:
    return a.x1 <= b.x0 or b.x1 <= a.x0 or a.y1 <= b.y0 or b.y1 <= a.y0


def test_every_label_lies_in_its_drawing_apart_from_the_others(design: Any) -> None:
    fig = dimensioned_figure(design)
    renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    try:
        for ax in fig.axes:
            frame = ax.get_window_extent(renderer)
            boxes = []
            for t in ax.texts:
                if not t.get_text().strip():
                    continue       # a dimension line's arrow is an annotation without text
                box = t.get_window_extent(renderer)
                if isinstance(t, (Annotation, Text)) and t.get_bbox_patch() is not None:
                    t.update_bbox_position_size(renderer)
                    box = Bbox.union([box, t.get_bbox_patch().get_window_extent(renderer)])
                # inside the drawing's frame (to a pixel)
                assert frame.x0 - 1 <= box.x0 and box.x1 <= frame.x1 + 1, (ax.get_title(), t.get_text())
                assert frame.y0 - 1 <= box.y0 and box.y1 <= frame.y1 + 1, (ax.get_title(), t.get_text())
                boxes.append((t.get_text(), box))
            legend = ax.get_legend()
            if legend is not None:
                boxes.append(("legend", legend.get_window_extent(renderer)))
            for i, (na, a) in enumerate(boxes):
                for nb, b in boxes[i + 1:]:
                    assert _apart(a, b), (ax.get_title(), na, nb)
            # ticks on both axes, read in millimetres
            if ax.get_xticks().size:
                assert ax.get_xlabel() == "x [mm]" and ax.get_ylabel() == "y [mm]", ax.get_title()
                labels = [t.get_text() for t in ax.get_xticklabels() if t.get_text()]
                assert len(labels) >= 3 and all(re.fullmatch(r"−?-?\d+(\.\d+)?", x) for x in labels), labels
        # every counterweight written whole: its link, mass and disc
        texts = [t.get_text() for ax in fig.axes for t in ax.texts]
        assert sum("counterweight on the" in t for t in texts) == 2
        assert any("counterweight on the rocker" in t for t in texts)
    finally:
        plt.close(fig)


@contextmanager
def _record_file(design: Any) -> Iterator[Path]:
    """The design's record written to a PDF file in a scratch directory, for poppler's tools to read."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "record.pdf"
        path.write_bytes(design_report_pdf(design, record=DesignRecord("press", "x", "-", BODY, "0" * 64)))
        yield path


@pytest.mark.skipif(shutil.which("pdftotext") is None, reason="poppler-utils' pdftotext reads the PDF's word boxes")
def test_the_pdf_drawings_page_has_no_word_over_another(design: Any) -> None:
    with _record_file(design) as path:
        html = subprocess.run(["pdftotext", "-bbox-layout", str(path), "-"], check=True, capture_output=True,
                              text=True).stdout
    pages = html.split("<page ")[1:]
    drawing = next(p for p in pages if "Dimensioned" in p)
    width, height = (float(v) for v in re.findall(r'width="([\d.]+)" height="([\d.]+)"', drawing)[0])
    lines = [[(float(a), float(b), float(c), float(d), w) for a, b, c, d, w in
              re.findall(r'<word xMin="([\d.]+)" yMin="([\d.]+)" xMax="([\d.]+)" yMax="([\d.]+)">([^<]*)</word>', line)]
             for line in drawing.split("<line ")[1:]]
    words = [w for line in lines for w in line]
    assert all(0 <= x0 and x1 <= width and 0 <= y0 and y1 <= height for x0, y0, x1, y1, _ in words)
    # words of different lines never share ink (1 pt of slack for the fonts' line gap)
    boxes = [(k, w) for k, line in enumerate(lines) for w in line]
    for i, (ka, a) in enumerate(boxes):
        for kb, b in boxes[i + 1:]:
            if ka == kb:
                continue
            overlap_x = min(a[2], b[2]) - max(a[0], b[0])
            overlap_y = min(a[3], b[3]) - max(a[1], b[1])
            assert overlap_x <= 1.0 or overlap_y <= 1.0, (a, b)
    text = " ".join(w[4] for w in words)
    # three drawings with their axes in millimetres, and both counterweights' labels whole
    assert text.count("[mm]") >= 6
    assert "counterweight on the crank:" in text and "counterweight on the rocker:" in text


@pytest.mark.skipif(shutil.which("pdftoppm") is None, reason="poppler-utils' pdftoppm renders the PDF's pages")
def test_no_page_of_the_record_is_near_empty(design: Any) -> None:
    with _record_file(design) as path:
        subprocess.run(["pdftoppm", "-r", "30", "-gray", str(path), str(path.parent / "page")], check=True)
        pages = sorted(path.parent.glob("page*.pgm"), key=lambda f: int(re.findall(r"\d+", f.stem)[-1]))
        assert len(pages) >= 6
        for n, page in enumerate(pages, 1):
            header, width_height, _, data = page.read_bytes().split(b"\n", 3)
            assert header == b"P5"
            w, h = (int(v) for v in width_height.split())
            ink = (np.frombuffer(data, dtype=np.uint8).reshape(h, w) < 200).any(axis=1)
            rows = np.flatnonzero(ink)
            # the footer (the record's name, request hash and page number) is the last band of ink: left out
            footer = rows[-1]
            while footer > 0 and ink[footer - 1]:
                footer -= 1
            body = rows[rows < footer - 1]
            # the page's own content spans at least a third of its height: a page left with a heading and a few
            # lines (a table pushed onto a page of its own) fails
            assert body.size and (body[-1] - body[0]) / h >= 1 / 3, (n, body[[0, -1]] if body.size else None, h)
