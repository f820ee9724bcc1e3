"""Links sized for strength at 360 samples: the fixed point's time and its passes against one analysis of the
same linkage timed in the same run, for the four-bar and the six-bar press of the examples; and one link's least
section found as the sizing does (candidates lightest first in blocks that double, each block's checks over all
angles and sections at once) against checking one candidate at a time until one passes. Best of five runs."""

from __future__ import annotations

import dataclasses
from typing import Any

import synth
from bench._timing import best_of
from mechsynth_client.schemas.strength import StrengthSizingIn
from synth.strength import beam_forces, size_link, size_links
from synth.strength.links import LinkSpec
from api.translate.strength import sizing_call

SAMPLES = 360
REPEAT = 5


def _case(example: dict[str, Any]) -> tuple[Any, ...]:
    body = StrengthSizingIn.model_validate({**example, "samples": SAMPLES})
    return sizing_call(body)


def main() -> None:
    examples = StrengthSizingIn.model_config["json_schema_extra"]["examples"]  # type: ignore[index]
    for name, example in zip(("four-bar", "six-bar press"), examples):
        linkage, speed, specs, limits = _case(example)
        t_an = best_of(lambda: synth.analyse(linkage, speed, samples=SAMPLES), REPEAT)
        result = size_links(linkage, speed, specs, limits, samples=SAMPLES)
        t_size = best_of(lambda: size_links(linkage, speed, specs, limits, samples=SAMPLES), REPEAT)
        passes = len(result.iterations)
        print(f"{name}: sizing {len(specs)} bars in {passes} passes ({passes} analyses): {t_size * 1e3:.1f} ms = "
              f"{t_size / t_an:.0f} analyses of {t_an * 1e3:.2f} ms; {t_size / passes / t_an:.1f} analyses a pass; "
              f"mass {result.mass:.3f} kg")
        link = max(specs, key=lambda n: len(specs[n].family.candidates()))
        forces = beam_forces(result.analysis, link)
        spec = specs[link]
        cands = spec.family.candidates()
        t_all = best_of(lambda: size_link(forces, spec, limits), REPEAT)

        def one_at_a_time() -> None:
            for c in cands:
                if size_link(forces, dataclasses.replace(spec, section=c), limits).passed:
                    return

        t_each = best_of(one_at_a_time, REPEAT)
        t_forces = best_of(lambda: beam_forces(result.analysis, link), REPEAT)
        k = [c.label for c in cands].index(result.links[link].section.label)
        print(f"  {link}: least section {cands[k].label}, candidate {k + 1} of {len(cands)}: found in "
              f"{t_all * 1e3:.2f} ms, one candidate at a time {t_each * 1e3:.2f} ms (ratio {t_each / t_all:.2f}); "
              f"its beam forces {t_forces * 1e3:.2f} ms")


if __name__ == "__main__":
    main()
