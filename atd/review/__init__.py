"""Looking back at runs: a recording (`atd run --record`) read back, drawn as a page
(`atd report`) or set against another (`atd compare`)."""
