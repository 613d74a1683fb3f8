"""The SVG form of the diagrams, drawn without any tool: self-contained, no script, no network.

Class diagrams stand in layers (bases and containers above what they
extend or hold); state diagrams on a grid of given positions, or a circle.
"""

from __future__ import annotations

import dataclasses
import html
import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the model calls this module to draw itself; it never imports the model at run time
    from iecoop.uml.model import ClassDiagram, Relation, StateDiagram, UmlClass

__all__ = ["class_svg", "state_svg"]


def class_svg(diagram: ClassDiagram) -> str:
    """A diagram-contained SVG: boxes in layers (bases and containers above), straight arrows.

    Parallel relations of one kind between the same two boxes are drawn as
    one arrow carrying every label. An arrow that would cross a layer of
    boxes, or run along its own layer, is routed through the free rows
    between the layers and, to change rows, down a lane on the right.
    """
    boxes = {c.name: _Box.measure(c) for c in diagram.classes}
    drawn = _merge_relations([r for r in diagram.relations if r.source in boxes and r.target in boxes])
    layers = _layer([c.name for c in diagram.classes], [(r.source, r.target) for r in drawn])
    rank = {name: i for i, layer in enumerate(layers) for name in layer}
    column = {name: i for layer in layers for i, name in enumerate(layer)}
    routed = [r for r in drawn if _needs_route(rank[r.source], rank[r.target], column[r.source], column[r.target])]
    slots = _gap_slots(routed, rank, len(layers))
    width, height = _place(layers, boxes, [max(70.0, 30.0 + 12.0 * len(s)) for s in slots])
    lanes = [r for r in routed if rank[r.source] != rank[r.target]]
    lane_x = {id(r): width + 14.0 * k for k, r in enumerate(lanes)}
    paths = _routes(routed, boxes, layers, rank, slots, lane_x)
    bottom = max([height, *(y + 20.0 for path in paths.values() for _, y in path)])
    out = _SvgWriter(width + 14.0 * len(lanes) + (20.0 if lanes else 0.0), bottom, diagram.title, list(boxes.values()))
    for r in drawn:
        out.relation(boxes[r.source], boxes[r.target], r, paths.get(id(r)))
    for box in boxes.values():
        out.box(box)
    return out.finish()


def _merge_relations(relations: Sequence[Relation]) -> list[Relation]:
    """One relation per (source, target, kind); the labels of parallel ones joined."""
    merged: dict[tuple[str, str, str], list[Relation]] = {}
    for r in relations:
        merged.setdefault((r.source, r.target, r.kind), []).append(r)
    result: list[Relation] = []
    for (source, target, kind), group in merged.items():
        if len(group) == 1:
            result.append(group[0])
            continue
        labels = [r.label + (f" {r.multiplicity}" if r.multiplicity else "") for r in group if r.label]
        result.append(dataclasses.replace(group[0], label=", ".join(labels), multiplicity=""))
    return result


def _needs_route(source_rank: int, target_rank: int, source_col: int, target_col: int) -> bool:
    """A straight line would cross other boxes: it skips a layer, or runs along one past a box."""
    if source_rank == target_rank:
        return abs(source_col - target_col) > 1
    return abs(source_rank - target_rank) > 1


def _ends(source_rank: int, target_rank: int, layers: int) -> tuple[int, int]:
    """The gap rows an arrow runs in near its source and near its target (gap g lies below layer g)."""
    if source_rank == target_rank:
        gap = source_rank if source_rank < layers - 1 or layers == 1 else source_rank - 1
        return gap, gap
    if target_rank > source_rank:
        return source_rank, target_rank - 1
    return source_rank - 1, target_rank


def _gap_slots(routed: Sequence[Relation], rank: Mapping[str, int], layers: int) -> list[list[int]]:
    """Per gap row, the routed arrows that run in it (each gets its own height)."""
    slots: list[list[int]] = [[] for _ in range(max(1, layers))]
    for r in routed:
        for gap in dict.fromkeys(_ends(rank[r.source], rank[r.target], layers)):
            slots[gap].append(id(r))
    return slots


def _routes(
    routed: Sequence[Relation],
    boxes: Mapping[str, _Box],
    layers: Sequence[Sequence[str]],
    rank: Mapping[str, int],
    slots: Sequence[Sequence[int]],
    lane_x: Mapping[int, float],
) -> dict[int, list[tuple[float, float]]]:
    bottoms = [max(boxes[n].y + boxes[n].h for n in layer) for layer in layers]
    used: dict[str, int] = {}

    def gap_y(gap: int, r: Relation) -> float:
        return bottoms[gap] + 18.0 + 12.0 * slots[gap].index(id(r))

    def port(name: str, below: bool) -> tuple[float, float]:
        # Several arrows at one box leave from different points of its edge.
        box = boxes[name]
        k = used.get(name, 0)
        used[name] = k + 1
        x = max(box.x + 6.0, box.x + box.w - 14.0 - 10.0 * k)
        return x, box.y + box.h if below else box.y

    paths: dict[int, list[tuple[float, float]]] = {}
    for r in routed:
        rs, rt = rank[r.source], rank[r.target]
        near_source, near_target = _ends(rs, rt, len(layers))
        ys, yt = gap_y(near_source, r), gap_y(near_target, r)
        start = port(r.source, near_source >= rs)
        end = port(r.target, near_target >= rt)
        if rs == rt:
            paths[id(r)] = [start, (start[0], ys), (end[0], ys), end]
        else:
            lane = lane_x[id(r)]
            paths[id(r)] = [start, (start[0], ys), (lane, ys), (lane, yt), (end[0], yt), end]
    return paths


def state_svg(diagram: "StateDiagram") -> str:
    """A diagram-contained SVG: states on the given grid positions (or a circle), labelled arrows.

    Names and labels share one size and the boxes are only as wide as the longest name, so that
    the five columns of the PackML model fit a 740 px text column with no text under 10 px.
    """
    box_w = math.ceil(max(90.0, _CHAR_EM * _STATE_TEXT * max(len(s) for s in diagram.states) + 2 * _PAD))
    box_h = 34
    centres: dict[str, tuple[float, float]] = {}
    if diagram.positions:
        missing = [s for s in diagram.states if s not in diagram.positions]
        if missing:
            raise ValueError(f"no position for the states {missing}")
        step_x, step_y = box_w + 70, box_h + 70
        for s in diagram.states:
            col, row = diagram.positions[s]
            centres[s] = (40 + box_w / 2 + col * step_x, 40 + box_h / 2 + row * step_y)
    else:
        radius = max(160.0, len(diagram.states) * (box_w + 30) / (2 * math.pi))
        for i, s in enumerate(diagram.states):
            angle = 2 * math.pi * i / len(diagram.states) - math.pi / 2
            centres[s] = (radius + box_w + 40 + radius * math.cos(angle), radius + 80 + radius * math.sin(angle))
    merged = diagram.merged()
    # A loop and its label stand right of the box; otherwise the right edge is the boxes'.
    loops = [len(" / ".join(labels)) for (source, target), labels in merged.items() if source == target]
    right = 30 + _CHAR_EM * _STATE_TEXT * max(loops) + 10 if loops else 24
    width = max(x for x, _ in centres.values()) + box_w / 2 + right
    height = max(y for _, y in centres.values()) + box_h / 2 + 40
    out = _SvgWriter(width, height, diagram.title)
    boxes = {s: _Box(s, [], centres[s][0] - box_w / 2, centres[s][1] - box_h / 2, box_w, box_h) for s in diagram.states}
    ix, iy = boxes[diagram.initial].x - 30, boxes[diagram.initial].y + box_h / 2
    out.parts.append(f'<circle cx="{ix:.1f}" cy="{iy:.1f}" r="7" fill="#222"/>')
    out.arrow((ix + 7, iy), (boxes[diagram.initial].x, iy), "open", dashed=False)
    for (source, target), labels in merged.items():
        label = " / ".join(labels)
        if source == target:
            b = boxes[source]
            x, y = b.x + b.w, b.y + 6
            out.parts.append(
                f'<path d="M{x:.1f},{y:.1f} c 30,-22 30,42 0,{b.h - 12:.1f}" fill="none" stroke="#333"/>'
            )
            out.text(x + 26, y + b.h / 2 - 4, label, size=_STATE_TEXT, anchor="start")
            continue
        shift = 6.0 if (target, source) in merged else 0.0
        start, end = _clip_pair(boxes[source], boxes[target], shift)
        out.arrow(start, end, "open", dashed=False)
        mx, my = (start[0] + end[0]) / 2, (start[1] + end[1]) / 2
        out.text(mx, my - 3, label, size=_STATE_TEXT, halo=True)
    for box in boxes.values():
        out.state(box)
    return out.finish()


_CHAR_W = 7.0
#: The advance of one character of the monospace font, in em.
_CHAR_EM = 0.62
#: Where along an arrow its label may stand (fractions of its length), in order of preference.
_ALONG = (0.5, 0.35, 0.65, 0.2, 0.8, 0.1, 0.9)
_LINE_H = 15.0
_PAD = 8.0
#: The size of every text of a state diagram: names and labels alike.
_STATE_TEXT = 12


@dataclasses.dataclass
class _Box:
    name: str
    lines: list[tuple[str, str]]  # (text, style): style is "", "abstract", "static"
    x: float
    y: float
    w: float
    h: float
    heading: str = ""
    italic: bool = False
    split: int = 0  # number of field lines (a rule separates fields and operations)

    @classmethod
    def measure(cls, uml: UmlClass) -> _Box:
        lines: list[tuple[str, str]] = [(f.text(), "static" if f.static else "") for f in uml.fields]
        lines += [
            (op.text() + (" {leaf}" if op.final else ""), "abstract" if op.abstract else "") for op in uml.operations
        ]
        if not uml.detailed and uml.role:
            lines = [(f"({uml.role})", "")]
        heading = f"«{uml.heading}»"
        widest = max([len(heading), len(uml.name) + 2, *(len(t) for t, _ in lines)])
        w = widest * _CHAR_W + 2 * _PAD
        h = 2 * _LINE_H + _PAD + (len(lines) * _LINE_H + _PAD if uml.detailed or lines else 0)
        return cls(uml.name, lines, 0, 0, w, h, heading, uml.abstract, len(uml.fields))

    @property
    def centre(self) -> tuple[float, float]:
        return self.x + self.w / 2, self.y + self.h / 2


def _layer(names: list[str], edges: list[tuple[str, str]]) -> list[list[str]]:
    """Longest-path layers: an edge's source (base, container) sits above its target."""
    children: dict[str, list[str]] = {n: [] for n in names}
    for source, target in edges:
        if source != target and target not in children[source]:
            children[source].append(target)
    # Drop the edges that close a cycle (a back-reference), found by depth-first search.
    state: dict[str, int] = {}
    kept: dict[str, list[str]] = {n: [] for n in names}

    def visit(n: str) -> None:
        state[n] = 1
        for c in children[n]:
            if state.get(c) == 1:
                continue
            kept[n].append(c)
            if c not in state:
                visit(c)
        state[n] = 2

    for n in names:
        if n not in state:
            visit(n)
    depth: dict[str, int] = {n: 0 for n in names}
    for _ in names:
        changed = False
        for n in names:
            for c in kept[n]:
                if depth[c] < depth[n] + 1:
                    depth[c] = depth[n] + 1
                    changed = True
        if not changed:
            break
    layers: list[list[str]] = [[] for _ in range(max(depth.values()) + 1)]
    for n in names:
        layers[depth[n]].append(n)
    # One barycentre pass: order each layer by the mean position of its parents.
    parents: dict[str, list[str]] = {n: [] for n in names}
    for n in names:
        for c in kept[n]:
            parents[c].append(n)
    for i in range(1, len(layers)):
        above = {n: k for k, n in enumerate(layers[i - 1])}

        def key(n: str, above: dict[str, int] = above) -> float:
            ps = [above[p] for p in parents[n] if p in above]
            return sum(ps) / len(ps) if ps else float(len(above))

        layers[i].sort(key=key)
    return layers


def _place(layers: list[list[str]], boxes: dict[str, _Box], gaps: Sequence[float] = ()) -> tuple[float, float]:
    """Centre each layer; ``gaps[i]`` is the height of the free row below layer ``i`` (70 by default)."""
    gap_x, margin = 40.0, 20.0
    widths = [sum(boxes[n].w for n in layer) + gap_x * (len(layer) - 1) for layer in layers]
    total_w = max(widths) + 2 * margin
    y = margin + 24
    gap_y = 70.0
    for i, (layer, layer_w) in enumerate(zip(layers, widths)):
        gap_y = gaps[i] if i < len(gaps) else 70.0
        x = (total_w - layer_w) / 2
        tallest = max(boxes[n].h for n in layer)
        for n in layer:
            boxes[n].x, boxes[n].y = x, y
            x += boxes[n].w + gap_x
        y += tallest + gap_y
    return total_w, y - gap_y + margin


def _overlap(a: tuple[float, float, float, float], b: tuple[float, float, float, float]) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def _clip(box: _Box, toward: tuple[float, float]) -> tuple[float, float]:
    """Where the line from the box's centre toward a point leaves the box."""
    cx, cy = box.centre
    dx, dy = toward[0] - cx, toward[1] - cy
    if dx == 0 and dy == 0:
        return cx, cy
    scale = min(box.w / 2 / abs(dx) if dx else math.inf, box.h / 2 / abs(dy) if dy else math.inf)
    return cx + dx * scale, cy + dy * scale


def _clip_pair(a: _Box, b: _Box, shift: float = 0.0) -> tuple[tuple[float, float], tuple[float, float]]:
    (ax, ay), (bx, by) = a.centre, b.centre
    length = math.hypot(bx - ax, by - ay) or 1.0
    nx, ny = -(by - ay) / length * shift, (bx - ax) / length * shift
    start = _clip(a, (bx + nx, by + ny))
    end = _clip(b, (ax + nx, ay + ny))
    return (start[0] + nx, start[1] + ny), (end[0] + nx, end[1] + ny)


class _SvgWriter:
    def __init__(self, width: float, height: float, title: str, boxes: Sequence[_Box] = ()) -> None:
        self.width, self.height = width, height
        self.parts: list[str] = []
        self.title = title
        #: The areas labels must not cover: the boxes, then each label written.
        self.taken: list[tuple[float, float, float, float]] = [(b.x, b.y, b.x + b.w, b.y + b.h) for b in boxes]

    def text(
        self, x: float, y: float, text: str, *, size: int = 12, anchor: str = "middle", style: str = "",
        halo: bool = False,
    ) -> None:
        attrs = f' font-style="italic"' if style == "abstract" else ""
        attrs += ' text-decoration="underline"' if style == "static" else ""
        attrs += ' font-weight="bold"' if style == "bold" else ""
        attrs += ' paint-order="stroke" stroke="#fff" stroke-width="3"' if halo else ""
        self.parts.append(
            f'<text x="{x:.1f}" y="{y:.1f}" font-size="{size}" text-anchor="{anchor}"{attrs}>{html.escape(text)}</text>'
        )

    def box(self, box: _Box) -> None:
        fill = "#eef4fb" if "INTERFACE" in box.heading else "#fdf7e3"
        self.parts.append(
            f'<rect x="{box.x:.1f}" y="{box.y:.1f}" width="{box.w:.1f}" height="{box.h:.1f}" '
            f'fill="{fill}" stroke="#333"/>'
        )
        cx = box.x + box.w / 2
        self.text(cx, box.y + _LINE_H, box.heading, size=10)
        self.text(cx, box.y + 2 * _LINE_H, box.name, style="abstract" if box.italic else "bold")
        if box.h <= 2 * _LINE_H + _PAD:
            return
        y = box.y + 2 * _LINE_H + _PAD
        self.parts.append(f'<line x1="{box.x:.1f}" y1="{y:.1f}" x2="{box.x + box.w:.1f}" y2="{y:.1f}" stroke="#333"/>')
        for i, (line, style) in enumerate(box.lines):
            if i == box.split and 0 < i:
                ry = y + i * _LINE_H + 3
                self.parts.append(
                    f'<line x1="{box.x:.1f}" y1="{ry:.1f}" x2="{box.x + box.w:.1f}" y2="{ry:.1f}" stroke="#999"/>'
                )
            self.text(box.x + _PAD, y + (i + 1) * _LINE_H, line, anchor="start", style=style, size=11)

    def state(self, box: _Box) -> None:
        self.parts.append(
            f'<rect x="{box.x:.1f}" y="{box.y:.1f}" width="{box.w:.1f}" height="{box.h:.1f}" rx="12" '
            f'fill="#eef4fb" stroke="#333"/>'
        )
        self.text(box.x + box.w / 2, box.y + box.h / 2 + 4, box.name, size=_STATE_TEXT, style="bold")

    def arrow(self, start: tuple[float, float], end: tuple[float, float], head: str, *, dashed: bool) -> None:
        dash = ' stroke-dasharray="6,4"' if dashed else ""
        self.parts.append(
            f'<line x1="{start[0]:.1f}" y1="{start[1]:.1f}" x2="{end[0]:.1f}" y2="{end[1]:.1f}" stroke="#333"{dash}/>'
        )
        self.head(end, start, head)

    def head(self, tip: tuple[float, float], tail: tuple[float, float], head: str) -> None:
        dx, dy = tip[0] - tail[0], tip[1] - tail[1]
        length = math.hypot(dx, dy) or 1.0
        ux, uy = dx / length, dy / length
        px, py = -uy, ux
        if head in ("triangle", "open"):
            size = 12.0 if head == "triangle" else 9.0
            bx, by = tip[0] - ux * size, tip[1] - uy * size
            left = (bx + px * size / 2, by + py * size / 2)
            right = (bx - px * size / 2, by - py * size / 2)
            if head == "triangle":
                points = f"{tip[0]:.1f},{tip[1]:.1f} {left[0]:.1f},{left[1]:.1f} {right[0]:.1f},{right[1]:.1f}"
                self.parts.append(f'<polygon points="{points}" fill="#fff" stroke="#333"/>')
            else:
                self.parts.append(
                    f'<polyline points="{left[0]:.1f},{left[1]:.1f} {tip[0]:.1f},{tip[1]:.1f} '
                    f'{right[0]:.1f},{right[1]:.1f}" fill="none" stroke="#333"/>'
                )
        else:  # a diamond at the tip
            size = 9.0
            mid = (tip[0] - ux * size, tip[1] - uy * size)
            back = (tip[0] - 2 * ux * size, tip[1] - 2 * uy * size)
            left = (mid[0] + px * size / 2, mid[1] + py * size / 2)
            right = (mid[0] - px * size / 2, mid[1] - py * size / 2)
            fill = "#333" if head == "filled-diamond" else "#fff"
            points = " ".join(f"{x:.1f},{y:.1f}" for x, y in (tip, left, back, right))
            self.parts.append(f'<polygon points="{points}" fill="{fill}" stroke="#333"/>')

    def relation(
        self, source: _Box, target: _Box, r: Relation, route: Sequence[tuple[float, float]] | None = None
    ) -> None:
        if route is None:
            start, end = _clip_pair(source, target)
            points = [start, end]
        else:
            points = list(route)
        dash = ' stroke-dasharray="6,4"' if r.kind == "implements" else ""
        path = " ".join(f"{x:.1f},{y:.1f}" for x, y in points)
        self.parts.append(f'<polyline points="{path}" fill="none" stroke="#333"{dash}/>')
        if r.kind in ("extends", "implements"):
            # The arrow points at the base / the interface: the source box.
            self.head(points[0], points[1], "triangle")
            return
        if r.kind == "composition":
            self.head(points[0], points[1], "filled-diamond")
        elif r.kind == "aggregation":
            self.head(points[0], points[1], "diamond")
        self.head(points[-1], points[-2], "open")
        label = r.label + (f" {r.multiplicity}" if r.multiplicity else "")
        if not label:
            return
        if route is None:
            (ax, ay), (bx, by) = points
            spots = [(ax + (bx - ax) * t + 4, ay + (by - ay) * t, "start") for t in _ALONG]
            spots += [(ax + (bx - ax) * t - 4, ay + (by - ay) * t, "end") for t in _ALONG]
        else:
            # On a routed arrow the label stands on a run along a free row: the first one if it has room.
            spots = []
            for (ax, ay), (bx, by) in zip(points[1:-2], points[2:-1]):
                if ay != by:
                    continue
                anchor, dx = ("start", 6) if bx >= ax else ("end", -6)
                spots += [(ax + dx + (bx - ax) * t, ay - 3, anchor) for t in (0.0, *_ALONG)]
        self.label(spots, label, size=10)

    def label(self, spots: Sequence[tuple[float, float, str]], text: str, *, size: int) -> None:
        """Write ``text`` at the first of ``spots`` where it covers no box and no other label (else the first)."""
        width = _CHAR_EM * size * len(text)

        def extent(x: float, y: float, anchor: str) -> tuple[float, float, float, float]:
            left = x - width / 2 if anchor == "middle" else x - width if anchor == "end" else x
            return left, y - size, left + width, y + 0.25 * size

        def free(area: tuple[float, float, float, float]) -> bool:
            return not any(_overlap(area, taken) for taken in self.taken)

        x, y, anchor = next((spot for spot in spots if free(extent(*spot))), spots[0])
        self.taken.append(extent(x, y, anchor))
        self.text(x, y, text, size=size, anchor=anchor, halo=True)

    def finish(self) -> str:
        title = f"<title>{html.escape(self.title)}</title>" if self.title else ""
        head = (
            f'<svg xmlns="http://www.w3.org/2000/svg" width="{self.width:.0f}" height="{self.height:.0f}" '
            f'viewBox="0 0 {self.width:.0f} {self.height:.0f}" font-family="DejaVu Sans Mono, Menlo, Consolas, monospace">'
        )
        background = f'<rect width="{self.width:.0f}" height="{self.height:.0f}" fill="#fff"/>'
        return "\n".join([head, title, background, *self.parts, "</svg>"]) + "\n"
