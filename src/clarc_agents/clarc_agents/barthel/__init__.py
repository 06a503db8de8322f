"""The Barthel index as knowledge: its items and options, the record of a test and its score, the
understanding of a spoken answer, and what CLARC says and shows at each step. Pure."""
