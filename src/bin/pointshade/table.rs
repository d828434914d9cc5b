//! The library's render options ([`pointshade::render::options::RENDER_OPTIONS`]) as flags: each
//! row becomes `--name-with-dashes VALUE`, and each value is handed over as text for
//! [`RenderOptions::set`] to read and check.

use clap::{Arg, ArgMatches, Args, Command, FromArgMatches};

use pointshade::error::InputResult;
use pointshade::render::options::{OptionValue, RenderOption, RenderOptions, Spelling, Values, RENDER_OPTIONS};

/// The render options given on the command line, as text, in the table's order.
pub struct OptionFlags(Vec<(&'static str, String)>);

impl OptionFlags {
    /// The options, read and checked; errors name the flag.
    pub fn options(&self) -> InputResult<RenderOptions> {
        let mut options = RenderOptions::default();
        for (name, text) in &self.0 {
            options.set(name, &OptionValue::Text(text.clone()), Spelling::Flag)?;
        }
        Ok(options)
    }
}

fn flag(option: &RenderOption) -> Arg {
    let arg = Arg::new(option.name)
        .long(option.name.replace('_', "-"))
        .value_name(option.placeholder)
        .help(option.help);
    let arg = match option.alias {
        Some(alias) => arg.visible_alias(alias),
        None => arg,
    };
    match option.values {
        // Lists and negative numbers start with a dash: `--view -30,20`, `--exposure -1`.
        Values::Numbers { .. } => arg.allow_hyphen_values(true),
        Values::Number { .. } | Values::Whole { .. } => arg.allow_negative_numbers(true),
        Values::Name(_) | Values::Names(_) => arg,
    }
}

impl FromArgMatches for OptionFlags {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        let given = RENDER_OPTIONS
            .iter()
            .filter_map(|o| matches.get_one::<String>(o.name).map(|text| (o.name, text.clone())))
            .collect();
        Ok(OptionFlags(given))
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}

impl Args for OptionFlags {
    fn augment_args(command: Command) -> Command {
        RENDER_OPTIONS.iter().fold(command, |c, o| c.arg(flag(o)))
    }

    fn augment_args_for_update(command: Command) -> Command {
        Self::augment_args(command)
    }
}
