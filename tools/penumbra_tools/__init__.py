"""Shared code of the developer tools under tools/ (standard library only, except the
Mitsuba comparison, which runs in build/venv-mitsuba). Scripts in tools/ import it as
`penumbra_tools`, since Python puts a script's own folder first on the module path."""
