"""Schemas of gear load capacity: POST /v1/gears/rating (ISO 6336 method B), and the strength sizing that
/v1/gears/drive and the machine design answer per stage."""

from __future__ import annotations

import math
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from .common import StrictModel, ValidityCheckOut, WarningOut, exactly_one

MM = 1e-3
UM = 1e-6
MPA = 1e6
RPM = math.pi / 30.0
MAX_SPECTRUM = 20_000
GRADES = ("case_hardened_ML", "case_hardened_MQ", "case_hardened_ME", "induction_hardened_MQ", "nitrided_MQ",
          "nitrided_through_hardened_MQ", "through_hardened_alloy_ML", "through_hardened_alloy_MQ",
          "through_hardened_alloy_ME", "normalised_steel_MQ", "nodular_cast_iron_MQ", "grey_cast_iron_MQ")
_MATERIAL = ("Material grade by name (ISO 6336-5 allowable stresses): " + ", ".join(GRADES)
             + "; GET /v1/gears/materials lists them with their values.")


class _DutyFields(StrictModel):
    application_factor: float = Field(1.0, ge=1, le=5, description="K_A: external overloads beyond the nominal "
                                      "torque [-]; 1 when the torque given is the real load.")
    life_h: float = Field(20000.0, gt=0, le=1e7, description="Required life [h].")
    min_safety_contact: float = Field(1.0, gt=0, le=10, description="S_Hmin, least pitting safety factor [-].")
    min_safety_root: float = Field(1.4, gt=0, le=10, description="S_Fmin, least tooth-root safety factor [-].")
    pitting_permitted: bool = Field(False, description="Use the S-N line of ISO 6336-2 that admits limited "
                                    "pitting (steels only).")


class LoadSpectrumIn(StrictModel):
    """The pinion torque sampled evenly in time over one machine cycle (the machine's real load)."""

    torque_Nm: list[float] = Field(min_length=1, max_length=MAX_SPECTRUM, description="Pinion torque at equal "
                                   "time steps over one cycle [N·m]; the sign is ignored (either flank counts).",
                                   examples=[[600.0, 900.0, 1200.0, 900.0, 600.0, 300.0]])


class RatingIn(_DutyFields):
    """An external spur or helical pair, its materials, lubrication and load: ISO 6336 method B rating."""

    pinion_teeth: int = Field(ge=5, le=1000, description="Teeth of the pinion z1.", examples=[17])
    gear_teeth: int = Field(ge=5, le=5000, description="Teeth of the gear z2.", examples=[103])
    normal_module_mm: float = Field(gt=0, le=100, description="Normal module m_n [mm].", examples=[8.0])
    face_width_mm: float = Field(gt=0, le=5000, description="Common face width b [mm].", examples=[100.0])
    helix_angle_deg: float = Field(0.0, ge=0, lt=45, description="Helix angle beta at the reference circle [deg].")
    pinion_profile_shift: float = Field(0.0, ge=-1, le=2, description="Profile shift coefficient x1 [-].")
    gear_profile_shift: float = Field(0.0, ge=-1, le=2, description="Profile shift coefficient x2 [-].")
    centre_distance_mm: float | None = Field(None, gt=0, le=1e5, description="Centre distance a [mm]; default "
                                             "the one the profile shifts give (it must agree within 0.05 m_n).")
    normal_pressure_angle_deg: float = Field(20.0, ge=10, le=30, description="Pressure angle of the basic rack "
                                             "[deg].")
    rack_dedendum: float = Field(1.25, ge=1, le=2, description="Dedendum of the basic rack h_fP/m_n [-] (1.25 "
                                 "ISO 53 A/B, 1.4 type D).")
    rack_root_radius: float = Field(0.38, ge=0.05, le=0.6, description="Root radius of the basic rack "
                                    "rho_fP/m_n [-].")
    accuracy_grade: int = Field(6, ge=1, le=11, description="ISO 1328-1 accuracy grade of both wheels.")
    pinion_material: str = Field("case_hardened_MQ", max_length=80, description=_MATERIAL)
    gear_material: str = Field("case_hardened_MQ", max_length=80, description=_MATERIAL)
    oil_viscosity_40C_mm2_s: float = Field(220.0, gt=0, le=1e5, description="Oil kinematic viscosity at 40 °C "
                                           "[mm²/s].")
    flank_roughness_Ra_um: float = Field(0.8, gt=0, le=50, description="Flank roughness R_a of both wheels "
                                         "[µm] (R_z = 6 R_a).")
    root_roughness_Rz_um: float = Field(10.0, gt=0, lt=16, description="Root roughness R_z [µm].")
    tip_relief_um: float | None = Field(None, ge=0, le=1000, description="Tip relief C_a [µm]; default the "
                                        "running-in value C_ay.")
    face_load_factor: float | None = Field(None, ge=1, le=10, description="K_Hbeta from your shaft analysis; "
                                           "default method C, pinion centred between its bearings.")
    max_face_width_ratio: float = Field(1.5, gt=0, le=5, description="Largest face width in pinion reference "
                                        "diameters b/d1 [-].")
    pinion_rim_thickness_mm: float | None = Field(None, gt=0, le=1e4, description="Rim thickness s_R under the "
                                                  "pinion's root [mm]; null: a solid wheel (Y_B = 1).")
    gear_rim_thickness_mm: float | None = Field(None, gt=0, le=1e4, description="Rim thickness s_R under the gear's "
                                                "root [mm]; null: a solid wheel (Y_B = 1).")
    pinion_speed_rpm: float = Field(gt=0, le=1e5, description="Pinion speed [rev/min].", examples=[360.0])
    pinion_torque_Nm: float | None = Field(None, gt=0, le=1e9, description="Nominal pinion torque [N·m] (times "
                                           "K_A); or give load_spectrum.", examples=[9000.0])
    load_spectrum: LoadSpectrumIn | None = Field(None, description="The pinion torque over the machine cycle: "
                                                 "life by Miner's rule; the rating is then at its peak.")

    model_config = ConfigDict(json_schema_extra={**exactly_one("pinion_torque_Nm", "load_spectrum"), "examples": [
        {"pinion_teeth": 17, "gear_teeth": 103, "normal_module_mm": 8.0, "face_width_mm": 100.0,
         "helix_angle_deg": 15.8, "pinion_profile_shift": 0.145, "centre_distance_mm": 500.0, "accuracy_grade": 5,
         "rack_dedendum": 1.4, "rack_root_radius": 0.39, "oil_viscosity_40C_mm2_s": 320.0,
         "flank_roughness_Ra_um": 1.0, "tip_relief_um": 70.0, "face_load_factor": 1.16, "life_h": 50000.0,
         "min_safety_root": 1.0, "pinion_speed_rpm": 360.0, "pinion_torque_Nm": 9000.0},
        {"pinion_teeth": 21, "gear_teeth": 64, "normal_module_mm": 3.0, "face_width_mm": 40.0,
         "pinion_material": "through_hardened_alloy_MQ", "gear_material": "through_hardened_alloy_MQ",
         "pinion_speed_rpm": 1450.0, "load_spectrum": {"torque_Nm": [40.0, 95.0, 160.0, 95.0, 40.0, 10.0]}},
    ]})

    @model_validator(mode="after")
    def _one_load(self) -> RatingIn:
        if (self.pinion_torque_Nm is None) == (self.load_spectrum is None):
            raise ValueError("give pinion_torque_Nm or load_spectrum, not both")
        return self

    def speed(self) -> float:
        """Pinion speed [rad/s]."""
        return self.pinion_speed_rpm * RPM


def mpa(v: tuple[float, float]) -> list[float]:
    """A pair of stresses [Pa] in MPa."""
    return [v[0] / MPA, v[1] / MPA]


class PairGeometryOut(BaseModel):
    """Involute geometry of the pair; lists are [pinion, gear]."""

    transverse_pressure_angle_deg: float = Field(description="alpha_t = atan(tan alpha_n / cos beta) [deg].")
    working_pressure_angle_deg: float = Field(description="alpha_wt at the centre distance, from inv(alpha_wt) "
                                              "= inv(alpha_t) + 2 tan alpha_n (x1 + x2)/(z1 + z2) [deg].")
    base_helix_angle_deg: float = Field(description="beta_b [deg].")
    centre_distance_mm: float = Field(description="Centre distance a used [mm].")
    centre_distance_from_shifts_mm: float = Field(description="Centre distance the profile shifts give [mm].")
    ratio: float = Field(description="Gear ratio u = z2/z1 [-].")
    reference_diameters_mm: list[float] = Field(description="d = z m_n / cos beta [mm].")
    base_diameters_mm: list[float] = Field(description="d_b = d cos alpha_t [mm].")
    tip_diameters_mm: list[float] = Field(description="d_a = d + 2 m_n (h_aP* + x) [mm].")
    root_diameters_mm: list[float] = Field(description="d_f = d - 2 m_n (h_fP* - x) [mm].")
    working_diameters_mm: list[float] = Field(description="d_w = d_b / cos alpha_wt [mm].")
    transverse_contact_ratio: float = Field(description="epsilon_alpha [-].")
    overlap_ratio: float = Field(description="epsilon_beta = b sin beta / (pi m_n) [-].")
    total_contact_ratio: float = Field(description="epsilon_gamma [-].")
    virtual_teeth: list[float] = Field(description="z_n = z / (cos² beta_b cos beta) [-].")


class FactorOut(BaseModel):
    """One factor of the rating, as a commercial report lists it."""

    symbol: str = Field(description="ISO 6336 symbol (K_V, Z_H, Y_F...).")
    name: str = Field(description="The factor in words, with the method used.")
    pinion: float = Field(description="Value for the pinion.")
    gear: float = Field(description="Value for the gear (equal to the pinion's for a factor of the pair).")
    unit: str = Field(description="Unit; empty for a dimensionless factor.")


class RatingChecksOut(BaseModel):
    """Independent checks of the rating."""

    hertz_contact_stress_MPa: float = Field(description="Hertz stress of two cylinders with the flanks' normal "
                                            "radii at the pitch point, times Z_eps Z_beta and the K factors; "
                                            "equals contact_stress_MPa / Z_B for the pinion.")
    power_balance: float = Field(description="F_t v / (T_1 omega_1); equals 1.")


class SpectrumOut(BaseModel):
    """Life on the load spectrum by Miner's rule on the S-N curves (Z_NT, Y_NT); lists are [pinion, gear]."""

    samples: int = Field(description="Torque samples over the cycle.")
    rms_torque_Nm: float = Field(description="RMS of the torque magnitudes [N·m].")
    mean_torque_Nm: float = Field(description="Mean of the torque magnitudes [N·m].")
    damage_contact: list[float] = Field(description="Miner sum over the required life, pitting [-]; < 1 lasts.")
    damage_root: list[float] = Field(description="Miner sum over the required life, tooth root [-].")
    life_contact_h: list[float | None] = Field(description="Hours until the pitting sum reaches 1; null: never.")
    life_root_h: list[float | None] = Field(description="Hours until the root sum reaches 1; null: never.")
    safety_contact: list[float] = Field(description="Factor on every contact stress that brings the sum to 1 over "
                                        "the required life [-].")
    safety_root: list[float] = Field(description="Factor on every root stress that brings the sum to 1 [-].")
    equivalent_torque_contact_Nm: list[float] = Field(description="Constant pinion torque with the same pitting "
                                                      "damage (K factors of the peak held) [N·m].")
    equivalent_torque_root_Nm: list[float] = Field(description="Constant pinion torque with the same root "
                                                   "damage [N·m].")


class RatingOut(BaseModel):
    """ISO 6336 method B rating of the pair; every list is [pinion, gear]."""

    geometry: PairGeometryOut = Field(description="Involute geometry of the pair.")
    pinion_torque_Nm: float = Field(description="Pinion torque rated (the spectrum's peak for a spectrum) [N·m].")
    tangential_force_N: float = Field(description="F_t = 2 T_1 / d_1 [N].")
    pitch_line_velocity_m_s: float = Field(description="v at the reference circle [m/s].")
    load_cycles: list[float] = Field(description="N_L of each wheel over the required life [-].")
    nominal_contact_stress_MPa: float = Field(description="sigma_H0 at the pitch point [MPa].")
    contact_stress_MPa: list[float] = Field(description="sigma_H = Z_B,D sigma_H0 sqrt(K_A K_V K_Hbeta "
                                            "K_Halpha) [MPa].")
    contact_limit_MPa: list[float] = Field(description="sigma_HG = sigma_Hlim Z_NT Z_L Z_v Z_R Z_W Z_X [MPa].")
    permissible_contact_stress_MPa: list[float] = Field(description="sigma_HP = sigma_HG / S_Hmin [MPa].")
    nominal_root_stress_MPa: list[float] = Field(description="sigma_F0 = F_t/(b m_n) Y_F Y_S Y_beta Y_B Y_DT "
                                                 "(ISO 6336-3 method B) [MPa].")
    root_stress_MPa: list[float] = Field(description="sigma_F = sigma_F0 K_A K_V K_Fbeta K_Falpha [MPa].")
    root_limit_MPa: list[float] = Field(description="sigma_FG = sigma_Flim Y_ST Y_NT Y_deltarelT Y_RrelT Y_X "
                                        "[MPa].")
    permissible_root_stress_MPa: list[float] = Field(description="sigma_FP = sigma_FG / S_Fmin [MPa].")
    safety_contact: list[float] = Field(description="S_H = sigma_HG / sigma_H [-].")
    safety_root: list[float] = Field(description="S_F = sigma_FG / sigma_F [-].")
    meets_minimum: bool = Field(description="Every safety factor reaches its minimum (on the spectrum when one "
                                "was given).")
    factors: list[FactorOut] = Field(description="Every factor of the rating with its value, name and method.")
    spectrum: SpectrumOut | None = Field(None, description="Life on the load spectrum; null for a nominal torque.")
    checks: RatingChecksOut = Field(description="Independent checks.")
    warnings: list[WarningOut] = Field(default_factory=list, description="Where the rating stops: the resonance "
                                       "ranges of ISO 6336-1 (gear_main_resonance, gear_intermediate_resonance, "
                                       "gear_subcritical_resonance).")
    validity: list[ValidityCheckOut] = Field(default_factory=list, description="Each condition the rating needs "
                                             "against its limit.")


class GearMaterialOut(BaseModel):
    """A material grade of the shipped table."""

    name: str = Field(description="Grade name, as a request names it.")
    group: str = Field(description="ISO 6336 material group (St, V, Eh, IF, NT, NV, GGG, GG): its S-N curves.")
    description: str = Field(description="The grade in words, with its hardness and quality.")
    sigma_Hlim_MPa: float = Field(description="Contact endurance limit [MPa].")
    sigma_Flim_MPa: float = Field(description="Root endurance limit (nominal stress number) [MPa].")
    hardness_HB: float = Field(description="Surface hardness [HB].")
    elastic_modulus_MPa: float = Field(description="Young's modulus [MPa].")
    poisson: float = Field(description="Poisson's ratio [-].")
    density_kg_m3: float = Field(description="Density [kg/m³].")


class StrengthIn(_DutyFields):
    """Size every cylindrical stage for strength (ISO 6336): module from ISO 54 and the least face width."""

    pinion_material: str = Field("through_hardened_alloy_MQ", max_length=80, description=_MATERIAL)
    gear_material: str = Field("through_hardened_alloy_MQ", max_length=80, description=_MATERIAL)
    helix_angle_deg: float | None = Field(None, ge=0, lt=45, description="Helix angle of every pair [deg]; "
                                          "default 0 for spur stages and 15 for helical ones.")
    pinion_teeth: int = Field(19, ge=5, le=200, description="Teeth of every pinion; the gear gets the nearest "
                              "whole number to the stage ratio times this.")
    accuracy_grade: int = Field(7, ge=1, le=11, description="ISO 1328-1 accuracy grade.")
    oil_viscosity_40C_mm2_s: float = Field(220.0, gt=0, le=1e5, description="Oil viscosity at 40 °C [mm²/s].")
    module_series: Literal["first", "first_and_second"] = Field(
        "first", description="ISO 54 modules to choose from: the first choice, or first and second.")
    min_face_width_ratio: float = Field(0.2, gt=0, le=2, description="Least face width in pinion diameters [-].")
    max_face_width_ratio: float = Field(1.0, gt=0, le=2, description="Largest face width in pinion diameters [-].")
    objective: Literal["mass", "centre_distance"] = Field("mass", description="Least mass of the wheels, or "
                                                          "least sum of centre distances.")


class SizedStageOut(BaseModel):
    """One stage sized for strength; lists are [pinion, gear]."""

    stage: int = Field(description="Stage index, motor side first.")
    module_mm: float = Field(description="Normal module from the ISO 54 series [mm].")
    pinion_teeth: int = Field(description="Teeth of the pinion.")
    gear_teeth: int = Field(description="Teeth of the gear.")
    ratio: float = Field(description="Tooth ratio z2/z1 [-].")
    helix_angle_deg: float = Field(description="Helix angle [deg].")
    face_width_mm: float = Field(description="Least face width meeting every minimum safety factor [mm].")
    centre_distance_mm: float = Field(description="Centre distance [mm].")
    reference_diameters_mm: list[float] = Field(description="Reference diameters [mm].")
    tip_diameters_mm: list[float] = Field(description="Tip diameters [mm].")
    mass_kg: float = Field(description="Both wheels as solid discs of the reference diameters [kg].")
    safety_contact: list[float] = Field(description="S_H (on the load spectrum when the load is one) [-].")
    safety_root: list[float] = Field(description="S_F (on the load spectrum when the load is one) [-].")
    pinion_torque_Nm: float = Field(description="Peak pinion torque the stage carries [N·m].")
    binding: str = Field(description="What fixes the face width: contact_pinion, contact_gear, root_pinion, "
                         "root_gear, or min_face_width.")
    margins: dict[str, float] = Field(description="S/S_min - 1 of each strength constraint [-].")
    smaller_module_mm: float | None = Field(description="The next smaller module of the series [mm]; null when "
                                            "there is none.")
    smaller_module_fails: str | None = Field(description="What that module fails at the same face width (a "
                                             "constraint name, or the geometry field); null when there is none.")
