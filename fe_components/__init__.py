"""fe_components package."""
