"""The Barthel index as knowledge: its items, options and bands, read from its test definition
(definitions/barthel.yaml). Pure. Running it is the generic questionnaire (questionnaire/)."""
