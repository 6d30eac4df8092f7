"""Files: result datasets (netCDF), checkpoints, ParaView export, atomic writes."""
