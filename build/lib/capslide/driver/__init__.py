"""Running a case: the load path observed by recording, snapshots, stops, progress and checkpoints."""
