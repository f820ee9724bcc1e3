"""POST /v1/gears/train: meshes and planetary stages in, the train's ratios, speeds and torques out."""

from __future__ import annotations

import math

import synth

from api.translate.linkage import warnings_out
from mechsynth_client.schemas.train import (
    TrainChecksOut,
    TrainIn,
    TrainMeshIn,
    TrainOut,
    TrainPlanetaryIn,
    TrainShaftOut,
    TrainWheelOut,
)


def train_mesh_from(mesh: TrainMeshIn) -> synth.GearMesh:
    """Engine mesh."""
    return synth.GearMesh(mesh.driving_teeth, mesh.driven_teeth, mesh.internal, mesh.idler, mesh.efficiency)


def train_planetary_from(stage: TrainPlanetaryIn) -> synth.PlanetaryStage:
    """Engine planetary stage."""
    return synth.PlanetaryStage(stage.sun_teeth, stage.planet_teeth, stage.ring_teeth, stage.fixed, stage.input,
                                stage.output, stage.planet_ring_teeth, stage.efficiency, stage.basic_efficiency,
                                stage.ring_internal)


def train_element_from(element: TrainMeshIn | TrainPlanetaryIn) -> synth.GearMesh | synth.PlanetaryStage:
    """Engine mesh or planetary stage."""
    return train_mesh_from(element) if isinstance(element, TrainMeshIn) else train_planetary_from(element)


def train_from(body: TrainIn) -> list[synth.GearMesh | synth.PlanetaryStage]:
    """Engine train elements."""
    return [train_element_from(e) for e in body.elements]


def train_out(r: synth.TrainResult) -> TrainOut:
    """Schema from an engine train result."""
    return TrainOut(
        ratio=r.ratio, output_direction=r.shafts[-1].direction, efficiency=r.efficiency,
        back_efficiency=r.back_efficiency, locked=r.locked, self_locking=r.self_locking,
        warnings=warnings_out(r.warnings),
        external_meshes=r.external_meshes,
        shafts=[TrainShaftOut(index=s.index, ratio=s.ratio, direction=s.direction, speed_rad_s=s.speed,
                              speed_rpm=None if s.speed is None else s.speed * 30 / math.pi,
                              wheels=list(s.wheels)) for s in r.shafts],
        wheels=[TrainWheelOut(name=w.name, teeth=w.teeth, shaft=w.shaft, pitch_diameter_m=w.pitch_diameter)
                for w in r.wheels],
        checks=TrainChecksOut(formula_ratio=r.formula_ratio, agrees=r.formula_agrees),
    )
