"""What a flight is asked to be: the scenario file (TOML: aircraft, duration, seed, [plant],
[sensors], [lqg], [[faults]]), the options its tables become (plant_options, sensor_options,
cdrw_params: every CDRW number a scenario may override), the faults it describes (faults:
kinds, fields, when they are active), their field schema and ScenarioError (schema), the
`hil faults` catalog, and the fault times of a campaign (campaign).

Modules: schema, cdrw_params, plant_options, sensor_options, faults, file, catalog, campaign.
How faults act on a reading or a frame is hil.sim's (sensor_faults, frame_faults).

Room 4: may import hil.util, hil.io, hil.bus (the DBC names the frames a fault may target).
"""
