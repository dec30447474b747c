"""Which modal stress images a report draws: a flexible body holding at least IMAGE_STRAIN_SHARE
(1 %) of a mode's strain energy, not one skipped as round-off (assembly.analysis.modal_stress)."""
from assembly.analysis.modal_stress import IMAGE_STRAIN_SHARE, ModalAmplitude, drawn


def test_a_body_with_a_negligible_share_of_the_mode_is_not_drawn():
    # the case of the report: a wheel holding 0.03 % of a pinion mode
    a = ModalAmplitude(3, 1.0, {"pinion": 0.9997, "wheel": 3e-4, "shaft": 1e-8}, ("shaft",), "pinion")
    assert drawn(a, "pinion") and not drawn(a, "wheel") and not drawn(a, "shaft")
    b = ModalAmplitude(4, 1.0, {"wheel": IMAGE_STRAIN_SHARE}, (), "wheel")
    assert drawn(b, "wheel")                        # at the stated share: drawn
