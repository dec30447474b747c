"""assembly package."""
