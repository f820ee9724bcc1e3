"""Text on a drawing laid out by measuring it: each label goes where its box lies inside its axes and clear of every
box already placed (other labels, the scale bar, the legend, the parts drawn), and ticks in millimetres on both axes
of a drawing to scale.

Measured with the figure's own renderer at the figure's final size and limits, so what is measured is what the
page shows.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

from matplotlib.axes import Axes
from matplotlib.text import Annotation
from matplotlib.ticker import FuncFormatter
from matplotlib.transforms import Bbox

# Where a label may go round its anchor [points]: near first, then further, the eight directions in turn.
_DIRECTIONS = ((1, -1), (1, 1), (-1, -1), (-1, 1), (1, 0), (-1, 0), (0, -1), (0, 1))
OFFSETS: tuple[tuple[float, float], ...] = tuple(
    (dx * r, dy * r) for r in (14.0, 30.0, 50.0, 75.0, 105.0) for dx, dy in _DIRECTIONS)
# Room kept between two boxes [pixels].
_GAP = 2.0


def mm_axes(ax: Axes) -> None:
    """Ticks in millimetres on both axes of a drawing whose data are in metres."""
    # to the micrometre: a tick at the origin computed as 1e-17 m reads 0, never 1e-14
    mm = FuncFormatter(lambda v, _: f"{round(v * 1e3, 3) + 0.0:g}")
    ax.xaxis.set_major_formatter(mm)
    ax.yaxis.set_major_formatter(mm)
    ax.set_xlabel("x [mm]", fontsize=8)
    ax.set_ylabel("y [mm]", fontsize=8)
    ax.tick_params(labelsize=7)


def freeze(ax: Axes) -> None:
    """Fix the axes' limits as drawn (equal aspect applied), so that what is measured next stays where it is."""
    ax.apply_aspect()
    ax.set_xlim(*ax.get_xlim())
    ax.set_ylim(*ax.get_ylim())
    ax.set_autoscale_on(False)


class Labels:
    """The boxes taken on one axes [display pixels] and the placing of labels among them."""

    def __init__(self, ax: Axes) -> None:
        self.ax = ax
        self.renderer = ax.figure.canvas.get_renderer()  # type: ignore[attr-defined]
        self.frame = ax.get_window_extent(self.renderer)
        self.taken: list[Bbox] = []
        self.sources: list[Any] = []

    def take(self, artists: Iterable[Any]) -> None:
        """Mark what these artists cover (patches, texts, the legend) as taken."""
        for a in artists:
            self.sources.append(a)
            box = a.get_window_extent(self.renderer)
            if box.width > 0 and box.height > 0:
                self.taken.append(box)

    def refresh(self) -> None:
        """Measure again after the limits changed: the frame and what the artists taken cover."""
        self.frame = self.ax.get_window_extent(self.renderer)
        sources, self.sources, self.taken = self.sources, [], []
        self.take(sources)

    def free(self, box: Bbox) -> bool:
        """Inside the axes and clear of every taken box."""
        inner = self.frame.padded(-_GAP)
        inside = inner.x0 <= box.x0 and box.x1 <= inner.x1 and inner.y0 <= box.y0 and box.y1 <= inner.y1
        return inside and not any(box.padded(_GAP).overlaps(t) for t in self.taken)

    def place(self, anchor: Sequence[float], text: str, offsets: Sequence[tuple[float, float]] = OFFSETS,
              leader: bool = False, **kw: Any) -> Annotation:
        """Put ``text`` at the first offset from ``anchor`` [data] where its box is free; if none is, at the one
        that overlaps least, so nothing is lost. ``leader``: a thin line from the anchor to the label."""
        best: tuple[float, Annotation] | None = None
        for dx, dy in offsets:
            ha = "left" if dx > 0 else "right" if dx < 0 else "center"
            va = "bottom" if dy > 0 else "top" if dy < 0 else "center"
            arrow = {"arrowstyle": "-", "lw": 0.5, "color": "0.4"} if leader else None
            ann = self.ax.annotate(text, (float(anchor[0]), float(anchor[1])), xytext=(dx, dy),
                                   textcoords="offset points", ha=ha, va=va, arrowprops=arrow,
                                   annotation_clip=False, **kw)
            box = self._box(ann)
            if self.free(box):
                if best is not None:
                    best[1].remove()
                self.taken.append(box)
                return ann
            cost = self._overlap(box)
            if best is None or cost < best[0]:
                if best is not None:
                    best[1].remove()
                best = (cost, ann)
            else:
                ann.remove()
        assert best is not None
        self.taken.append(self._box(best[1]))
        return best[1]

    def _box(self, ann: Annotation) -> Bbox:
        # the text with its rounded box (bbox patch) round it, without the leader line
        text_box = ann.get_window_extent(self.renderer)
        patch = ann.get_bbox_patch()
        if patch is not None:
            ann.update_bbox_position_size(self.renderer)
            return Bbox.union([text_box, patch.get_window_extent(self.renderer)])
        return text_box

    def _overlap(self, box: Bbox) -> float:
        inside = Bbox.intersection(box, self.frame)
        outside = box.width * box.height - (inside.width * inside.height if inside is not None else 0.0)
        shared = 0.0
        for t in self.taken:
            both = Bbox.intersection(box, t)
            if both is not None:
                shared += both.width * both.height
        return 10.0 * outside + shared


def scale_bar(ax: Axes, labels: Labels, span: float) -> None:
    """A scale bar in millimetres in a free corner of the axes (the lower strip kept for it when no corner is
    free): the drawing is to scale."""
    raw = span / 4
    mag = 10 ** math.floor(math.log10(raw))
    length = max(s * mag for s in (1, 2, 5, 10) if s * mag <= raw)
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    w, h = x1 - x0, y1 - y0
    corners = ((x0 + 0.04 * w, y0 + 0.05 * h), (x1 - 0.04 * w - length, y0 + 0.05 * h),
               (x0 + 0.04 * w, y1 - 0.12 * h), (x1 - 0.04 * w - length, y1 - 0.12 * h))
    for x, y in corners:
        line = ax.plot([x, x + length], [y, y], "k-", lw=2.5, solid_capstyle="butt")[0]
        text = ax.text(x, y + 0.015 * h, f"{length * 1e3:g} mm", fontsize=7, va="bottom")
        box = Bbox.union([line.get_window_extent(labels.renderer), text.get_window_extent(labels.renderer)])
        if labels.free(box):
            labels.taken.append(box)
            return
        line.remove()
        text.remove()
    # no corner free: a strip below everything drawn
    ax.set_ylim(y0 - 0.12 * h, y1)
    freeze(ax)
    labels.refresh()
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    w, h = x1 - x0, y1 - y0
    y = y0 + 0.03 * h
    line = ax.plot([x0 + 0.04 * w, x0 + 0.04 * w + length], [y, y], "k-", lw=2.5, solid_capstyle="butt")[0]
    text = ax.text(x0 + 0.04 * w, y + 0.01 * h, f"{length * 1e3:g} mm", fontsize=7, va="bottom")
    labels.taken.append(Bbox.union([line.get_window_extent(labels.renderer), text.get_window_extent(labels.renderer)]))
