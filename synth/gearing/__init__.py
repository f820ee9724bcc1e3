"""Drive design: stage types, ratio splitting, tooth numbers, shaft speeds and torques, motor choice, and load
capacity (ISO 6336) with sizing for strength."""

from .involute import BasicRack, PairGeometry, pair_geometry
from .life import SpectrumRating, rate_spectrum
from .materials import GearMaterial, gear_material, gear_materials
from .rating import Duty, GearPairSpec, RatingChecks, RatingFactor, RatingResult, rate_pair
from .sizing import (
    SizedStage,
    SizingRules,
    StageLoad,
    StrengthSplit,
    TrainSizing,
    module_series,
    size_stage,
    size_train,
    split_for_strength,
)
from .drive import DriveChecks, DriveResult, DriveShaft, design_drive
from .motors import CatalogueMotor, find_motor, motor_catalogue, select_motor
from .split import (
    InertiaModel,
    SplitChecks,
    SplitResult,
    build_split_program,
    default_snap_tolerance,
    gear_volume,
    r20_values,
    reduced_train_inertia,
    split_ratio,
    total_ratio,
)
from .stages import Stage, StageSpec, StageType, chain_efficiency, make_stage, make_stages, stage_types
from .teeth import (
    Mesh,
    ToothChecks,
    ToothResult,
    ToothRules,
    enumerate_tooth_numbers,
    interference_limit,
    serial_tooth_numbers,
    train_ratio,
    undercut_limit,
)
from .planetary import PlanetaryMesh, planetary_tooth_numbers
from .tooth_search import tooth_numbers
from .train import GearMesh, PlanetaryStage, TrainResult, TrainShaft, TrainWheel, gear_train

__all__ = [
    "DriveChecks", "DriveResult", "InertiaModel", "Mesh", "CatalogueMotor", "DriveShaft", "SplitChecks", "SplitResult", "Stage",
    "StageSpec", "StageType", "ToothChecks", "ToothResult", "ToothRules", "build_split_program",
    "chain_efficiency", "default_snap_tolerance", "design_drive", "enumerate_tooth_numbers", "find_motor",
    "gear_volume", "interference_limit", "make_stage", "make_stages", "motor_catalogue", "r20_values",
    "reduced_train_inertia", "select_motor", "serial_tooth_numbers", "split_ratio", "stage_types", "tooth_numbers", "total_ratio",
    "train_ratio", "undercut_limit",
    "BasicRack", "Duty", "GearMaterial", "GearPairSpec", "PairGeometry", "RatingFactor", "RatingResult", "RatingChecks", "SizedStage", "SizingRules", "SpectrumRating", "StageLoad", "StrengthSplit", "TrainSizing", "gear_material", "gear_materials", "module_series", "pair_geometry", "rate_pair", "rate_spectrum", "size_stage", "size_train", "split_for_strength",
    "GearMesh", "PlanetaryMesh", "PlanetaryStage", "planetary_tooth_numbers", "TrainResult", "TrainShaft", "TrainWheel", "gear_train",
]
