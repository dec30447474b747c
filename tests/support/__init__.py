"""Test fixtures shared by the test packages: small scikit-fem models and the
generator of the committed test meshes (``meshes/``)."""
