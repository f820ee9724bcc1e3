// Linkages to start a drawing from: points [m] (frame points grounded), links through them (the first two points set
// a link's frame), blocks on guides through a frame point.
const F = (name, x, y) => ({ name, x, y, ground: true });
const J = (name, x, y) => ({ name, x, y, ground: false });
const L = (name, ...points) => ({ name, points });
const fourbar = [F("O", 0, 0), F("Q", 0.3, 0), J("A", 0, 0.1), J("B", 0.3, 0.5)];
const fourbarLinks = [L("crank", "O", "A"), L("coupler", "A", "B")];

export const TEMPLATES = {
  fourbar: { label: "four-bar", model: { points: fourbar, links: [...fourbarLinks, L("rocker", "Q", "B")], blocks: [], crank: "crank", output: "rocker", branches: {} } },
  slider_crank: { label: "slider-crank", model: { points: [F("O", 0, 0), F("G", 0.5, 0), J("A", 0, 0.1), J("B", 0.3, 0)],
    links: [L("crank", "O", "A"), L("rod", "A", "B")], blocks: [{ name: "slider", point: "B", through: "G", axis_deg: 0 }],
    crank: "crank", output: "slider", branches: {} } },
  quick_return: { label: "quick-return (offset slider-crank)", model: { points: [F("O", 0, 0), F("G", 0.6, -0.15), J("A", 0, 0.1), J("B", 0.35, -0.15)],
    links: [L("crank", "O", "A"), L("rod", "A", "B")], blocks: [{ name: "ram", point: "B", through: "G", axis_deg: 0 }],
    crank: "crank", output: "ram", branches: {} } },
  watt: { label: "Watt six-bar", model: { points: [...fourbar, F("R", 0.8, 0), J("C", 0.6, 0.4), J("D", 0.9, 0.6)],
    links: [...fourbarLinks, L("rocker", "Q", "B", "C"), L("link", "C", "D"), L("follower", "R", "D")], blocks: [],
    crank: "crank", output: "follower", branches: {} } },
  press: { label: "six-bar press", model: { points: [...fourbar, F("G", 0.9, 0), J("C", 0.6, 0.4), J("D", 0.9, 1.0)],
    links: [...fourbarLinks, L("rocker", "Q", "B", "C"), L("rod", "C", "D")], blocks: [{ name: "ram", point: "D", through: "G", axis_deg: 90 }],
    crank: "crank", output: "ram", branches: {} },
  loads: [{ type: "window", force_N: 2000, start_deg: 200, end_deg: 300 }] },
  // the two ternary links not joined to each other: the frame (O, Q, R) and the coupler (A, B, C)
  stephenson: { label: "Stephenson six-bar", model: { points: [...fourbar, J("C", 0, 0.5), F("R", 0.7, 0.2), J("D", 0.5, 0.7)],
    links: [L("crank", "O", "A"), L("coupler", "A", "B", "C"), L("rocker", "Q", "B"), L("link", "C", "D"), L("follower", "R", "D")], blocks: [],
    crank: "crank", output: "follower", branches: {} } },
  // the slotted lever: a block at the crank pin in the lever's slot, the lever's end in a slot across the ram
  shaper: { label: "shaper (slotted lever)", model: { points: [F("O", 0, 0), F("O1", 0, -0.3), F("G", 0.5, 0.3), J("A", 0.06, 0.08), J("B", 0.09, 0.27), J("R", 0.09, 0.3)],
    links: [L("crank", "O", "A"), L("rocker", "O1", "B")],
    blocks: [{ name: "slider", point: "A", slot: "rocker", axis_deg: 0 }, { name: "ram", point: "R", through: "G", axis_deg: 0 },
      { name: "ram_slider", point: "B", slot: "ram", axis_deg: 90 }], crank: "crank", output: "ram", branches: {} } },
  toggle: { label: "toggle press", model: { points: [F("O", 0, 0), F("Q", 0.5, 0.3), F("G", 0.5, -0.5), J("A", 0.1, 0), J("B", 0.5, 0), J("D", 0.5, -0.3)],
    links: [L("crank", "O", "A"), L("coupler", "A", "B"), L("rocker", "Q", "B"), L("toggle", "B", "D")],
    blocks: [{ name: "ram", point: "D", through: "G", axis_deg: 90 }], crank: "crank", output: "ram", branches: {} } },
};
