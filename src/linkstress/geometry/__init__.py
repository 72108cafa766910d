"""A link's geometry: its profile, outline and bounds, sections, mass properties, members and their
cuts, curved centrelines and the curved-beam stress on them."""
