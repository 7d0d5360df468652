"""One module per source paper; each registers its validation cases with :func:`mjrft.tools.validation.case`."""
