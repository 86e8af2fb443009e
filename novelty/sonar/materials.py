"""Wall materials and how they return a sonar echo.

A Polaroid ranger works at about 49.4 kHz, a wavelength of about 7 mm in air
(Polaroid, 1987). A surface much smoother than that behaves as an acoustic
mirror: it sends the pulse on in the specular direction and returns an echo
only when the beam meets it near normal incidence; a rough surface scatters
part of the energy back over a wider range of angles (Kuc & Siegel, 1987;
Bozma & Kuc, 1991). Each :class:`Material` sums both behaviours in one lobe.

Echo strength
-------------
A pulse arriving along unit direction ``u`` at a surface of normal ``n`` would
be mirrored along ``u_s = u - 2 (u . n) n``. The strength sent towards a
receiver in direction ``v`` is

    s = reflectivity * exp(-psi^2 / (2 * lobe^2))                         (1)

where ``psi`` is the angle between ``v`` and ``u_s``. For a direct echo
(``v = -u``) ``psi`` is twice the incidence angle, so a material returns a
direct echo on the beam axis up to an incidence angle of

    theta_max = lobe * sqrt(2 * ln(reflectivity)) / 2                     (2)

(:meth:`Material.max_incidence`; strengths are in units of the ranger's
detection threshold, so ``s >= 1`` is heard). ``specular`` is the fraction of
the energy mirrored on, which a second surface may return (a multipath echo,
read as a range longer than the true one; see :mod:`novelty.sonar.ranger`).

The defaults are chosen, approximately, to give the behaviour reported for
real indoor surfaces: painted breezeblock (open-textured concrete block) is
heard to about 40 degrees incidence; smooth (fair-faced) brick, whose mortar
joints are grooves about as wide as the wavelength, to about 30 degrees;
varnished wood to about 13 degrees; glass and laminated plastic only within a
few degrees of normal (Kuc & Siegel, 1987, section IV; Leonard & Durrant-Whyte, 1992,
chapter 2, who found smooth walls invisible beyond about 15-20 degrees).

References
----------
Polaroid Corporation (1987). Ultrasonic Ranging System (handbook and 6500
series ranging module data sheet). Cambridge, MA.

Kuc, R. & Siegel, M. W. (1987). Physically based simulation model for
acoustic sensor robot navigation. IEEE Trans. PAMI, 9(6), 766-778.

Bozma, O. & Kuc, R. (1991). Characterizing pulses reflected from rough
surfaces using ultrasound. J. Acoust. Soc. Am., 89(6), 2519-2531.

Leonard, J. J. & Durrant-Whyte, H. F. (1992). Directed Sonar Sensing for
Mobile Robot Navigation. Kluwer.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Material", "MATERIALS", "get_material"]


@dataclass(frozen=True)
class Material:
    """How a surface returns ultrasound (equation (1) of the module).

    Parameters
    ----------
    name : str
        Key in :data:`MATERIALS`.
    reflectivity : float
        Echo strength at normal incidence on the beam axis, in units of the
        detection threshold (``>= 1`` is heard). Absorbent surfaces (clothing)
        are low; hard surfaces high.
    lobe : float
        Angular width (degrees, one standard deviation) of the reflected
        energy around the mirror direction. Small for smooth surfaces.
    specular : float
        Fraction of the energy mirrored on, in [0, 1]; a second surface may
        send it back (multipath).
    description : str
        What the surface is, for documentation and plots.
    colour : str
        A matplotlib colour for plots.
    """

    name: str
    reflectivity: float
    lobe: float
    specular: float
    description: str = ""
    colour: str = "0.3"

    def strength(self, psi):
        """Equation (1): echo strength at angle ``psi`` (radians) from the mirror direction."""
        lobe = math.radians(self.lobe)
        return self.reflectivity * np.exp(-0.5 * (np.asarray(psi) / lobe) ** 2)

    def max_incidence(self) -> float:
        """Equation (2): the largest incidence angle (degrees) giving an on-axis echo."""
        if self.reflectivity <= 1.0:
            return 0.0
        return self.lobe * math.sqrt(2.0 * math.log(self.reflectivity)) / 2.0


# Chosen values (approximately; see the module docstring for the sources of
# the behaviour they reproduce). max_incidence(): breezeblock ~40 deg, brick ~31,
# plaster ~22, cardboard ~21, wood ~13, glass ~5, laminate ~6.
MATERIALS: dict[str, Material] = {
    m.name: m
    for m in (
        Material("breezeblock", reflectivity=6.0, lobe=42.0, specular=0.3,
                 description="painted breezeblock: open-textured concrete block, rough at 7 mm "
                             "wavelength, heard over a wide range of angles",
                 colour="#8c8c8c"),
        Material("wood", reflectivity=8.0, lobe=13.0, specular=0.8,
                 description="varnished wood (doors, frames): smooth, mostly specular",
                 colour="#a0522d"),
        Material("brick", reflectivity=8.0, lobe=30.0, specular=0.5,
                 description="smooth (fair-faced) brick: smooth faces, but mortar joints about "
                             "a wavelength wide scatter at oblique incidence",
                 colour="#b5533c"),
        Material("glass", reflectivity=12.0, lobe=4.5, specular=0.97,
                 description="glass: an acoustic mirror, heard only near normal incidence",
                 colour="#5fa8d3"),
        Material("laminate", reflectivity=10.0, lobe=5.5, specular=0.95,
                 description="laminated, shiny plastic (display boards): near-mirror",
                 colour="#e0a526"),
        Material("plaster", reflectivity=7.0, lobe=22.0, specular=0.6,
                 description="painted plaster (office walls): moderately smooth",
                 colour="#b0a999"),
        Material("cardboard", reflectivity=4.0, lobe=25.0, specular=0.4,
                 description="cardboard (boxes): soft, fairly diffuse",
                 colour="#c8a165"),
        Material("metal", reflectivity=14.0, lobe=6.0, specular=0.97,
                 description="sheet metal (bins, cabinets): strong mirror",
                 colour="#4f6d7a"),
        Material("fabric", reflectivity=2.0, lobe=45.0, specular=0.1,
                 description="clothing (a person): absorbent and diffuse, a weak echo",
                 colour="#6a4c93"),
        Material("aperture", reflectivity=0.0, lobe=1.0, specular=0.0,
                 description="no surface: marks an opening for ground truth, transparent to sound",
                 colour="none"),
    )
}


def get_material(name: str) -> Material:
    """The material called ``name``, with the known names in the error."""
    try:
        return MATERIALS[name]
    except KeyError:
        raise ValueError(f"Unknown material {name!r}; known: {', '.join(MATERIALS)}.") from None
